// Adaptive refine (surface_emitter_refine.h).
//
// Scaling and overflow: positions Q16.16 metres in int64 (the clip:
// emitter_clip3.h). Factors UQ0.32 summed over <= 6 points in uint64. A ratio is UQ0.32 (<= 1: the clipped polygon lies inside
// the node's). f (UQ0.32) x ratio -> Q32 irradiance per unit exitance;
// g (Q8.23 per metre) x ratio (Q32) >> 23 -> Q32 per metre, as the solver's
// gathers (surface_emitter_solve.cc). Coverage means: area (Q32.32 m^2,
// < 2^64) x fraction (<= 2^32) summed over <= 4 children, < 2^98. Their
// first moments: OffsetMomentQ32 (surface_emitter_moments.h); the moment term of an unrefined
// send: MomentTerm (surface_emitter_refine_send.cc).
#include "surface_emitter_refine.h"

#include <algorithm>

#include "emitter_clip3.h"
#include "point_polygon_factor.h"
#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"
#include "surface_emitter_frame.h"
#include "surface_emitter_moments.h"
#include "relight/base/worker_pool.h"

namespace relight {
namespace {

constexpr int kStackNodes = 1024;
// Receivers further than this many of their radii from the polygon take the
// factor at their centroid only.
constexpr int64_t kFarRadii = 4;

const int32_t* CornerQ16(const BakeHierarchy& h, const BakeMesh& mesh, uint32_t node, int k) {
  return &mesh.positions[3 * size_t{h.node_corners[size_t{node} * kBakeMaxNodeCorners + static_cast<size_t>(k)]}];
}

// Coverage moments: a covered fraction (Q32, <= 2^32) times a centre offset
// (OffsetMomentQ32, surface_emitter_moments.h). A real first moment is below 2^49 (a fraction of 1 times half a 32 km
// node); kMomentLimit bounds what a hostile bake could make of it, so a
// child's area (< 2^64) times it, over <= 4 children, stays below 2^117.
constexpr int64_t kMomentLimit = int64_t{1} << 50;

int64_t GradientTerm(int64_t gu, int64_t gv, const int32_t* uv_q16) {
  return RoundShiftSat64(static_cast<Int128>(gu) * uv_q16[0] + static_cast<Int128>(gv) * uv_q16[1], -16);
}

// Unit normal (Q1.30) of a Newell normal of any scale.
void UnitNormal(const Int128 normal[3], int32_t out_q30[3]) {
  UInt128 big = 0;
  for (int i = 0; i < 3; ++i)
    if (Abs128(normal[i]) > big) big = Abs128(normal[i]);
  const int shift = BitLength128(big) > 60 ? BitLength128(big) - 60 : 0;
  const int64_t v[3] = {static_cast<int64_t>(normal[0] >> shift), static_cast<int64_t>(normal[1] >> shift),
                        static_cast<int64_t>(normal[2] >> shift)};
  if (v[0] == 0 && v[1] == 0 && v[2] == 0) {
    out_q30[0] = out_q30[1] = out_q30[2] = 0;
    return;
  }
  NormaliseQ30(v, out_q30);
}

}  // namespace

Status SurfaceEmitterRefine::Open(const Bake& bake, int pool_links, int refine_bits) {
  if (!bake.hierarchy) return Status(StatusCode::kUnsupported, "bake has no hierarchy");
  if (pool_links < 0) return Status(StatusCode::kInvalidArgument, "surface emitter: refine pool < 0 links");
  if (refine_bits < 0 || refine_bits > 32) {
    return Status(StatusCode::kInvalidArgument,
                  StrFormat("surface emitter: refine threshold 2^-%d outside 2^0..2^-32 "
                            "(EngineOptions::emitter_refine_bits)", refine_bits));
  }
  h_ = &*bake.hierarchy;
  mesh_ = &bake.mesh;
  const BakeHierarchy& h = *h_;
  const uint32_t n = h.node_count();
  if (n >= kPartialJob) return Status(StatusCode::kOutOfRange, "surface emitter: more than 2^31 hierarchy nodes");
  centroid_q16_.assign(size_t{n} * 3, 0);
  centre_uv_q16_.assign(size_t{n} * 2, 0);
  normal_q30_.assign(bake.mesh.surface_names.size() * 3, 0);
  drop_axis_.assign(bake.mesh.surface_names.size(), 0);
  frame_u_q30_.assign(bake.mesh.surface_names.size() * 3, 0);
  frame_v_q30_.assign(bake.mesh.surface_names.size() * 3, 0);
  tree_end_.assign(n, 0);
  SurfaceFrameQ30 frame{};
  uint32_t root = 0;
  for (uint32_t k = 0; k < n; ++k) {
    if (h.node_parent[k] == kBakeNoIndex) {
      if (k > 0) tree_end_[root] = k;
      root = k;
      MakeSurfaceFrameQ30(h, bake.mesh, k, &frame);
      const size_t s = h.node_surface[k];
      for (int i = 0; i < 3; ++i) {
        frame_u_q30_[3 * s + static_cast<size_t>(i)] = frame.u_q30[i];
        frame_v_q30_[3 * s + static_cast<size_t>(i)] = frame.v_q30[i];
      }
      Int128 normal[3];
      NodeNormalQ32(h, bake.mesh, k, normal);
      UnitNormal(normal, &normal_q30_[3 * s]);
      drop_axis_[s] = static_cast<uint8_t>(frame.drop_axis);
    }
    NodeCentreUvQ16(h, bake.mesh, frame, k, &centre_uv_q16_[2 * size_t{k}]);
    // Area centroid in 3D: fan triangles weighted by their area projected
    // along the surface's axis (proportional to the true areas).
    const int a_axis = (frame.drop_axis + 1) % 3, b_axis = (frame.drop_axis + 2) % 3;
    const int32_t* c0 = CornerQ16(h, bake.mesh, k, 0);
    Int128 weight = 0, sum[3] = {0, 0, 0};
    for (int j = 1; j + 1 < h.node_corner_count[k]; ++j) {
      const int32_t* b = CornerQ16(h, bake.mesh, k, j);
      const int32_t* c = CornerQ16(h, bake.mesh, k, j + 1);
      const Int128 w = static_cast<Int128>(int64_t{b[a_axis]} - c0[a_axis]) * (int64_t{c[b_axis]} - c0[b_axis]) -
                       static_cast<Int128>(int64_t{c[a_axis]} - c0[a_axis]) * (int64_t{b[b_axis]} - c0[b_axis]);
      weight += w;
      for (int i = 0; i < 3; ++i) sum[i] += w * (int64_t{b[i]} + c[i] - 2 * int64_t{c0[i]});
    }
    for (int i = 0; i < 3; ++i)
      centroid_q16_[3 * size_t{k} + i] = c0[i] + (weight == 0 ? 0 : static_cast<int64_t>(DivRound(sum[i], 3 * (weight < 0 ? -weight : weight)) * (weight < 0 ? -1 : 1)));
  }
  if (n > 0) tree_end_[root] = n;
  receiver_radius_q16_.assign(n, 0);
  for (uint32_t k = 0; k < n; ++k) {
    int64_t corners[kBakeMaxNodeCorners][3], centre[3];
    Bound(corners, Corners(k, corners), centre, &receiver_radius_q16_[k]);
  }
  // Per source node, the link sides its light leaves through.
  send_offsets_.assign(size_t{n} + 1, 0);
  for (uint32_t i = 0; i < h.link_count(); ++i) {
    if (h.link_f_pq[i] != 0) ++send_offsets_[h.link_q[i] + 1];
    if (h.link_f_qp[i] != 0) ++send_offsets_[h.link_p[i] + 1];
  }
  for (uint32_t k = 0; k < n; ++k) send_offsets_[k + 1] += send_offsets_[k];
  send_.assign(send_offsets_[n], 0);
  std::vector<uint32_t> fill(send_offsets_.begin(), send_offsets_.end() - 1);
  for (uint32_t i = 0; i < h.link_count(); ++i) {
    if (h.link_f_pq[i] != 0) send_[fill[h.link_q[i]]++] = 2 * i;
    if (h.link_f_qp[i] != 0) send_[fill[h.link_p[i]]++] = 2 * i + 1;
  }
  coverage_mean_q32_.assign(n, 0);
  coverage_moment_q32_.assign(size_t{n} * 2, 0);
  for (Part& part : parts_) {
    part.e0.assign(n, 0);
    part.eu.assign(n, 0);
    part.ev.assign(n, 0);
    part.pool.assign(static_cast<size_t>(pool_links), NewLink{0, 0, 0, 0});
  }
  jobs_.assign(n, 0);
  // BF's threshold on F x B (UQ0.32) for the emitter's light.
  refine_threshold_q32_ = uint64_t{1} << (32 - refine_bits);
  return Status::Ok();
}

int SurfaceEmitterRefine::Corners(uint32_t node, int64_t (*out)[3]) const {
  const int count = h_->node_corner_count[node];
  for (int k = 0; k < count; ++k)
    for (int i = 0; i < 3; ++i) out[k][i] = CornerQ16(*h_, *mesh_, node, k)[i];
  return count;
}

// The centre of a polygon's corners and their largest distance from it.
void SurfaceEmitterRefine::Bound(const int64_t (*poly)[3], int count, int64_t centre[3], int64_t* radius) {
  for (int i = 0; i < 3; ++i) centre[i] = 0;
  for (int k = 0; k < count; ++k)
    for (int i = 0; i < 3; ++i) centre[i] += poly[k][i];
  for (int i = 0; i < 3; ++i) centre[i] = count == 0 ? 0 : centre[i] / count;
  UInt128 largest = 0;
  for (int k = 0; k < count; ++k) {
    Int128 d2 = 0;
    for (int i = 0; i < 3; ++i) d2 += static_cast<Int128>(poly[k][i] - centre[i]) * (poly[k][i] - centre[i]);
    largest = std::max(largest, static_cast<UInt128>(d2));
  }
  *radius = static_cast<int64_t>(ISqrt128(largest));
}

// True when the receiver's centroid is further from the polygon's nearest
// possible point (its bound) than kFarRadii of the receiver's radius.
// Squares of Q16.16 differences (< 2^33) in Int128.
bool SurfaceEmitterRefine::Far(uint32_t receiver, const int64_t centre[3], int64_t radius) const {
  const int64_t* c = &centroid_q16_[3 * size_t{receiver}];
  Int128 d2 = 0;
  for (int i = 0; i < 3; ++i) d2 += static_cast<Int128>(c[i] - centre[i]) * (c[i] - centre[i]);
  const Int128 reach = static_cast<Int128>(radius) + kFarRadii * receiver_radius_q16_[receiver];
  return d2 > reach * reach;
}

// Sum of F from the receiver's quadrature points to the polygon: half way
// from its centroid to each corner (a quad's 2 x 2 bilinear midpoints when it
// is a parallelogram), so the mean is this over the corner count.
uint64_t SurfaceEmitterRefine::SumFactorsQ32(uint32_t receiver, const int64_t (*poly)[3], int count,
                                             const int64_t centre[3], int64_t radius,
                                             int64_t gradient_q32[2]) const {
  const BakeHierarchy& h = *h_;
  const size_t surface = h.node_surface[receiver];
  const int32_t* n = &normal_q30_[3 * surface];
  const int64_t* c = &centroid_q16_[3 * size_t{receiver}];
  const int corners = h.node_corner_count[receiver];
  if (gradient_q32 == nullptr && Far(receiver, centre, radius)) {
    // Far from the polygon the factor is nearly linear over the receiver:
    // its centroid alone gives the mean (a quarter of the kernel's cost).
    const int64_t x[3] = {c[0], c[1], c[2]};
    return uint64_t{PointToPolygonFactorQ32(x, n, poly, count)} * static_cast<uint64_t>(corners);
  }
  uint64_t sum = 0;
  uint32_t value[kBakeMaxNodeCorners];
  int64_t d[kBakeMaxNodeCorners][2];  // point - centroid along u, v: Q8 metres
  for (int k = 0; k < corners; ++k) {
    const int32_t* corner = CornerQ16(h, *mesh_, receiver, k);
    const int64_t x[3] = {(c[0] + corner[0]) / 2, (c[1] + corner[1]) / 2, (c[2] + corner[2]) / 2};
    value[k] = PointToPolygonFactorQ32(x, n, poly, count);
    sum += value[k];
    if (gradient_q32 == nullptr) continue;
    for (int a = 0; a < 2; ++a) {
      const int32_t* axis = a == 0 ? &frame_u_q30_[3 * surface] : &frame_v_q30_[3 * surface];
      const Int128 dot = static_cast<Int128>(x[0] - c[0]) * axis[0] + static_cast<Int128>(x[1] - c[1]) * axis[1] +
                         static_cast<Int128>(x[2] - c[2]) * axis[2];
      d[k][a] = RoundShiftSat64(dot, -38);  // Q16 x Q30 -> Q8
    }
  }
  if (gradient_q32 == nullptr) return sum;
  // Least squares: G = M^-1 sum_k d_k (v_k - mean), M = sum_k d_k d_k^T.
  // d < 2^23 (Q8, < 32 km), so M < 2^49, det < 2^99; values - mean < 2^33.
  const int64_t mean = static_cast<int64_t>(sum / static_cast<uint64_t>(corners));
  Int128 m00 = 0, m01 = 0, m11 = 0, b0 = 0, b1 = 0;
  for (int k = 0; k < corners; ++k) {
    m00 += static_cast<Int128>(d[k][0]) * d[k][0];
    m01 += static_cast<Int128>(d[k][0]) * d[k][1];
    m11 += static_cast<Int128>(d[k][1]) * d[k][1];
    b0 += static_cast<Int128>(d[k][0]) * (int64_t{value[k]} - mean);
    b1 += static_cast<Int128>(d[k][1]) * (int64_t{value[k]} - mean);
  }
  const Int128 det = m00 * m11 - m01 * m01;
  gradient_q32[0] = gradient_q32[1] = 0;
  if (det <= 0) return sum;
  // adj(M) b < 2^49 x 2^59; / det gives Q32 per Q8 metre, x 2^8 per metre.
  gradient_q32[0] = RoundShiftSat64(DivRound((m11 * b0 - m01 * b1) * 256, det), 0);
  gradient_q32[1] = RoundShiftSat64(DivRound((m00 * b1 - m01 * b0) * 256, det), 0);
  return sum;
}

namespace {

struct PartJob {
  SurfaceEmitterRefine* refine;
  const EmitterClip3* clip;
  int threads;
};

}  // namespace

Status SurfaceEmitterRefine::FirstShot(uint32_t root, const SurfaceEmitterShape& shape, const int64_t* coverage_q32,
                                       int64_t* leaf_irradiance_q32, WorkerPool* workers) {
  return Shoot(root, &shape, coverage_q32, leaf_irradiance_q32, workers);
}

Status SurfaceEmitterRefine::FractionalFirstShot(uint32_t root, const int64_t* coverage_q32,
                                                 int64_t* leaf_irradiance_q32, WorkerPool* workers) {
  return Shoot(root, nullptr, coverage_q32, leaf_irradiance_q32, workers);
}

Status SurfaceEmitterRefine::Shoot(uint32_t root, const SurfaceEmitterShape* shape, const int64_t* coverage_q32,
                                   int64_t* leaf_irradiance_q32, WorkerPool* workers) {
  const BakeHierarchy& h = *h_;
  const uint32_t n = h.node_count(), end = tree_end_[root];
  // How much of each node the emitter covers (area-weighted, as FE's pull).
  for (uint32_t k = end; k-- > root;) {
    if (h.leaf(k)) {
      coverage_mean_q32_[k] = coverage_q32[k];
      continue;
    }
    Int128 sum = 0;
    const uint32_t first = h.node_first_child[k], last = first + h.node_child_count[k];
    for (uint32_t c = first; c < last; ++c) sum += static_cast<Int128>(h.node_area[c]) * coverage_mean_q32_[c];
    const Int128 area = static_cast<Int128>(h.node_area[k]);
    coverage_mean_q32_[k] = area == 0 ? 0 : static_cast<int64_t>(sum / area);
    int64_t* moment = &coverage_moment_q32_[2 * size_t{k}];
    moment[0] = moment[1] = 0;
    if (coverage_mean_q32_[k] <= 0) continue;  // only covered nodes send
    // The first moment as the solver's pull has it: m_k = sum_c A_c (m_c + B_c (c_c - c_k)) / A_k.
    const int32_t* ck = &centre_uv_q16_[2 * size_t{k}];
    Int128 m[2] = {0, 0};
    for (uint32_t c = first; c < last; ++c) {
      const int64_t b = coverage_mean_q32_[c];
      if (b == 0) continue;
      const int32_t* cc = &centre_uv_q16_[2 * size_t{c}];
      for (int a = 0; a < 2; ++a) {
        const int64_t term = AddSat64(coverage_moment_q32_[2 * size_t{c} + a], OffsetMomentQ32(b, int64_t{cc[a]} - ck[a]));
        m[a] += static_cast<Int128>(h.node_area[c]) * std::clamp(term, -kMomentLimit, kMomentLimit);
      }
    }
    for (int a = 0; a < 2; ++a) moment[a] = area == 0 ? 0 : static_cast<int64_t>(m[a] / area);
  }
  // Fig. 5 from the root: fully covered subtrees send as they are; a partly
  // covered node's links get new factors for its clipped part. The walk
  // only lists the sources; the parts send (surface_emitter_refine_send.cc).
  uint32_t stack[kStackNodes];
  int depth = 0;
  stack[depth++] = root;
  job_count_ = 0;
  while (depth > 0) {
    const uint32_t s = stack[--depth];
    if (coverage_mean_q32_[s] <= 0) continue;
    if (coverage_mean_q32_[s] >= kOne) {
      AddJobs(s);
      continue;
    }
    jobs_[job_count_++] = s | kPartialJob;
    const uint32_t first = h.node_first_child[s];
    for (uint32_t c = first; c < first + h.node_child_count[s]; ++c) {
      if (depth == kStackNodes) return Status(StatusCode::kInternal, "surface emitter: quadtree too deep");
      stack[depth++] = c;
    }
  }
  EmitterClip3 clip;
  if (shape != nullptr) clip.Set(*shape, drop_axis_[h.node_surface[root]]);
  const EmitterClip3* cut = shape != nullptr ? &clip : nullptr;
  if (workers != nullptr && workers->threads() > 1) {
    PartJob job{this, cut, workers->threads()};
    workers->Run(
        [](void* context, int thread) {
          const PartJob& j = *static_cast<const PartJob*>(context);
          for (int p = thread; p < kParts; p += j.threads) j.refine->RunPart(p, j.clip);
        },
        &job);
  } else {
    for (int p = 0; p < kParts; ++p) RunPart(p, cut);
  }
  size_t needed = 0;
  for (const Part& part : parts_) needed += part.needed;
  if (needed > parts_[0].pool.size()) {
    return Status(StatusCode::kOutOfRange,
                  StrFormat("surface emitter (adaptive refine): the polygon needs %zu new links, more than "
                            "the %zu the refine pool holds (EngineOptions::emitter_refine_links)",
                            needed, parts_[0].pool.size()));
  }
  // The parts in order: part 1's sends, then every new link, into part 0's arrays.
  int64_t* e0 = parts_[0].e0.data();
  int64_t* eu = parts_[0].eu.data();
  int64_t* ev = parts_[0].ev.data();
  for (uint32_t k = 0; k < n; ++k) {
    e0[k] = AddSat64(e0[k], parts_[1].e0[k]);
    eu[k] = AddSat64(eu[k], parts_[1].eu[k]);
    ev[k] = AddSat64(ev[k], parts_[1].ev[k]);
  }
  for (const Part& part : parts_) {
    for (size_t i = 0; i < part.needed; ++i) {
      const NewLink& l = part.pool[i];
      e0[l.receiver] = AddSat64(e0[l.receiver], l.e0_q32);
      eu[l.receiver] = AddSat64(eu[l.receiver], l.eu_q32);
      ev[l.receiver] = AddSat64(ev[l.receiver], l.ev_q32);
    }
  }
  last_links_ = static_cast<int>(needed);
  // Push down as the solver does: each node's field about its surface's
  // origin, a child adds its parent's, a leaf takes the field at its centroid.
  for (uint32_t k = 0; k < n; ++k) {
    const int32_t* uv = &centre_uv_q16_[2 * size_t{k}];
    e0[k] = SubSat64(e0[k], GradientTerm(eu[k], ev[k], uv));
    const uint32_t parent = h.node_parent[k];
    if (parent != kBakeNoIndex) {
      e0[k] = AddSat64(e0[k], e0[parent]);
      eu[k] = AddSat64(eu[k], eu[parent]);
      ev[k] = AddSat64(ev[k], ev[parent]);
    }
  }
  for (uint32_t k = 0; k < n; ++k) {
    leaf_irradiance_q32[k] =
        h.leaf(k) ? AddSat64(e0[k], GradientTerm(eu[k], ev[k], &centre_uv_q16_[2 * size_t{k}])) : 0;
  }
  return Status::Ok();
}

}  // namespace relight
