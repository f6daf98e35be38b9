// Fixed-point hierarchical solve (surface_emitter_solve.h).
//
// Scaling and overflow: B (exitance) Q32, at most ~2^36 for unit emission
// (B <= S / (1 - rho)). A gather sums f (UQ0.32) x B into Int128 (Q64, <
// 2^68 x links) and g (Q8.23) x B (Q55); both are rounded back to int64 Q32
// (per metre for g). Moving a gradient's term between a node's centroid and
// the surface origin multiplies Q32 by Q16.16 metres in Int128. Reflectance
// UQ32 (2^32 = 1) x irradiance Q32 -> Int128, rounded back to Q32. Pull:
// child weights UQ32 x B Q32, summed in Int128.
#include "surface_emitter_solve.h"

#include "relight/base/fixed_ops.h"
#include "surface_emitter_frame.h"

namespace relight {
namespace {

// The gradient's part of the irradiance at (u, v) Q16.16 metres, Q32.
int64_t GradientTerm(int64_t gu, int64_t gv, const int32_t* uv_q16) {
  return RoundShiftSat64(static_cast<Int128>(gu) * uv_q16[0] + static_cast<Int128>(gv) * uv_q16[1],
                         -16);
}

}  // namespace

Status HierarchySolveQ32::Init(const Bake& bake) {
  if (!bake.hierarchy) return Status(StatusCode::kUnsupported, "bake has no hierarchy");
  h_ = &*bake.hierarchy;
  const BakeHierarchy& h = *h_;
  const uint32_t n = h.node_count();
  gather_offsets_.assign(size_t{n} + 1, 0);
  for (uint32_t i = 0; i < h.link_count(); ++i) {
    if (h.link_f_pq[i] != 0) ++gather_offsets_[h.link_p[i] + 1];
    if (h.link_f_qp[i] != 0) ++gather_offsets_[h.link_q[i] + 1];
  }
  for (uint32_t k = 0; k < n; ++k) gather_offsets_[k + 1] += gather_offsets_[k];
  const uint32_t entries = gather_offsets_[n];
  gather_source_.assign(entries, 0);
  gather_f_.assign(entries, 0);
  gather_g_.assign(size_t{entries} * 2, 0);
  std::vector<uint32_t> fill(gather_offsets_.begin(), gather_offsets_.end() - 1);
  const auto add = [&](uint32_t to, uint32_t from, uint32_t f, const int32_t* g) {
    const uint32_t e = fill[to]++;
    gather_source_[e] = from;
    gather_f_[e] = f;
    gather_g_[2 * size_t{e}] = g[0];
    gather_g_[2 * size_t{e} + 1] = g[1];
  };
  for (uint32_t i = 0; i < h.link_count(); ++i) {
    if (h.link_f_pq[i] != 0) add(h.link_p[i], h.link_q[i], h.link_f_pq[i], &h.link_g_pq[2 * size_t{i}]);
    if (h.link_f_qp[i] != 0) add(h.link_q[i], h.link_p[i], h.link_f_qp[i], &h.link_g_qp[2 * size_t{i}]);
  }
  child_weight_q32_.assign(n, 0);
  centre_uv_q16_.assign(size_t{n} * 2, 0);
  rho_q32_.assign(size_t{n} * 3, 0);
  run_begin_.clear();
  SurfaceFrameQ30 frame{};
  for (uint32_t k = 0; k < n; ++k) {
    if (h.node_parent[k] == kBakeNoIndex) {
      MakeSurfaceFrameQ30(h, bake.mesh, k, &frame);
      run_begin_.push_back(k);
    } else {
      const UInt128 num = static_cast<UInt128>(h.node_area[k]) << 32;
      child_weight_q32_[k] = static_cast<uint64_t>(num / h.node_area[h.node_parent[k]]);
    }
    NodeCentreUvQ16(h, bake.mesh, frame, k, &centre_uv_q16_[2 * size_t{k}]);
    // A leaf reflects with the albedo of its corner 0, as the baker's patch does.
    const uint32_t corner = h.node_corners[size_t{k} * kBakeMaxNodeCorners];
    for (int c = 0; c < 3; ++c) {
      const uint64_t albedo = bake.mesh.albedo[3 * size_t{corner} + static_cast<size_t>(c)];
      rho_q32_[3 * size_t{k} + static_cast<size_t>(c)] = ((albedo << 32) + 32767) / 65535;
    }
  }
  run_begin_.push_back(n);
  g0_.assign(size_t{n} * 3, 0);
  gu_.assign(size_t{n} * 3, 0);
  gv_.assign(size_t{n} * 3, 0);
  return Status::Ok();
}

void HierarchySolveQ32::Pull(uint32_t begin, uint32_t end, int64_t* b) const {
  const BakeHierarchy& h = *h_;
  for (uint32_t k = end; k-- > begin;) {  // children come after their parents
    if (h.leaf(k)) continue;
    Int128 sum[3] = {0, 0, 0};
    const uint32_t first = h.node_first_child[k];
    for (uint32_t c = first; c < first + h.node_child_count[k]; ++c)
      for (int ch = 0; ch < 3; ++ch) sum[ch] += static_cast<Int128>(child_weight_q32_[c]) * b[3 * size_t{c} + ch];
    for (int ch = 0; ch < 3; ++ch) b[3 * size_t{k} + ch] = RoundShiftSat64(sum[ch], -32);
  }
}

int HierarchySolveQ32::SolveRgb(const int64_t* emitted_q32, int64_t* b, const int64_t* first_shot_q32,
                                int64_t peak_floor_q32) {
  const BakeHierarchy& h = *h_;
  const uint32_t n = h.node_count();
  for (uint32_t k = 0; k < n; ++k)
    for (int ch = 0; ch < 3; ++ch) b[3 * size_t{k} + ch] = h.leaf(k) ? emitted_q32[k] : 0;
  const size_t runs = run_begin_.size() - 1;
  for (size_t r = 0; r < runs; ++r) Pull(run_begin_[r], run_begin_[r + 1], b);
  int64_t previous = 0;
  int sweep = 0;
  while (sweep < kEmitterSolveMaxSweeps) {
    ++sweep;
    int64_t change = 0, peak = peak_floor_q32;
    for (size_t r = 0; r < runs; ++r) {
      const uint32_t begin = run_begin_[r], end = run_begin_[r + 1];
      for (uint32_t k = begin; k < end; ++k) {  // gather
        const uint32_t e0 = gather_offsets_[k], e1 = gather_offsets_[k + 1];
        int64_t* g0 = &g0_[3 * size_t{k}];
        int64_t* gu = &gu_[3 * size_t{k}];
        int64_t* gv = &gv_[3 * size_t{k}];
        // Two passes over the node's links keep each pass's sums in registers.
        Int128 a0 = 0, a1 = 0, a2 = 0;
        for (uint32_t e = e0; e < e1; ++e) {
          const int64_t* src = &b[3 * size_t{gather_source_[e]}];
          const Int128 f = gather_f_[e];
          a0 += f * src[0];
          a1 += f * src[1];
          a2 += f * src[2];
        }
        g0[0] = RoundShiftSat64(a0, -32);
        g0[1] = RoundShiftSat64(a1, -32);
        g0[2] = RoundShiftSat64(a2, -32);
        gu[0] = gu[1] = gu[2] = gv[0] = gv[1] = gv[2] = 0;
        if (h.leaf(k)) continue;  // a leaf's links carry no gradient
        for (int ch = 0; ch < 3; ++ch) {
          Int128 du = 0, dv = 0;
          for (uint32_t e = e0; e < e1; ++e) {
            const int64_t src = b[3 * size_t{gather_source_[e]} + ch];
            du += static_cast<Int128>(gather_g_[2 * size_t{e}]) * src;
            dv += static_cast<Int128>(gather_g_[2 * size_t{e} + 1]) * src;
          }
          gu[ch] = RoundShiftSat64(du, -kBakeGradientFracBits);
          gv[ch] = RoundShiftSat64(dv, -kBakeGradientFracBits);
          // About the surface's origin, so a child adds it as it is.
          g0[ch] = SubSat64(g0[ch], GradientTerm(gu[ch], gv[ch], &centre_uv_q16_[2 * size_t{k}]));
        }
      }
      for (uint32_t k = begin + 1; k < end; ++k) {  // push
        const size_t parent = 3 * size_t{h.node_parent[k]};
        for (int ch = 0; ch < 3; ++ch) {
          g0_[3 * size_t{k} + ch] = AddSat64(g0_[3 * size_t{k} + ch], g0_[parent + ch]);
          gu_[3 * size_t{k} + ch] = AddSat64(gu_[3 * size_t{k} + ch], gu_[parent + ch]);
          gv_[3 * size_t{k} + ch] = AddSat64(gv_[3 * size_t{k} + ch], gv_[parent + ch]);
        }
      }
      for (uint32_t k = begin; k < end; ++k) {
        if (!h.leaf(k)) continue;
        for (int ch = 0; ch < 3; ++ch) {
          const size_t i = 3 * size_t{k} + ch;
          // Saturating: a bake whose links pass validation cannot make these
          // overflow, but a runaway solve must not reach signed overflow either.
          int64_t e = AddSat64(g0_[i], GradientTerm(gu_[i], gv_[i], &centre_uv_q16_[2 * size_t{k}]));
          if (first_shot_q32 != nullptr) e = AddSat64(e, first_shot_q32[k]);
          const int64_t updated =
              AddSat64(emitted_q32[k], RoundShiftSat64(static_cast<Int128>(rho_q32_[i]) * e, -32));
          const int64_t d = SaturateI64(updated > b[i] ? Int128{updated} - b[i] : Int128{b[i]} - updated);
          if (d > change) change = d;
          if (updated > peak) peak = updated;
          b[i] = updated;
        }
      }
      Pull(begin, end, b);
    }
    if (change == 0) break;
    // change >= 2^55 would overflow the 128-bit test below; such a solve is
    // far from converged anyway.
    if (sweep >= 2 && change < previous && change < (int64_t{1} << 55)) {
      // Remaining ~ change r / (1 - r), r = change / previous, capped at 0.99.
      const Int128 lhs = static_cast<Int128>(change) << kEmitterSolveToleranceLog2;
      const bool capped = Int128{change} * 100 >= Int128{previous} * 99;
      const bool done = capped ? lhs * 99 < peak
                               : lhs * change < static_cast<Int128>(peak) * (previous - change);
      if (done) break;
    }
    previous = change;
  }
  return sweep;
}

}  // namespace relight
