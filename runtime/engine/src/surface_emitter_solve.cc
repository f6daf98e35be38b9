// Fixed-point hierarchical solve (surface_emitter_solve.h).
//
// Scaling and overflow: B (exitance) Q32 int64, at most ~2^36 for unit
// emission (B <= S / (1 - rho)). Gathers read B as int32 Q24 (the "view",
// saturated to +-view_limit_) and an inner source's first moment m as int32
// Q20 x metres (saturated the same). A gather's exitance sum is
// sum f x view (UQ0.32 x Q24 = Q56) + 2^t sum (w_u m_u + w_v m_v), the
// moment weights w = f g_rev / f_rev stored as int32 Q(36 - t) per metre
// (t chosen at Init so the largest fits), so the moment products are
// Q(56 - t) and x 2^t is Q56 too. Init sets view_limit_ = (2^63 - 1) / (the
// largest over the nodes of sum f + 2^t sum (|w_u| + |w_v|), sum |g_u| or
// sum |g_v|), capped at 2^31 - 1, so no sum reaches 2^63; a bake's factors
// sum to about 1 per node, so the cap is what applies and unit emission
// reads exactly up to B = 128 (m up to 2048 x m). Q56 is shifted to Q32;
// g (Q8.23) x view is Q47, shifted to Q32 per metre. Moving a gradient's
// term between a node's centroid and the surface origin multiplies Q32 by
// Q16.16 metres in Int128. Reflectance UQ32 (2^32 = 1) x irradiance Q32 ->
// Int128, rounded back to Q32. Pull: child weights UQ32 x (B Q32, m Q32 x
// m + B x (child centre - parent centre) Q16 m >> 16), summed in Int128.
#include "surface_emitter_solve.h"

#include <cstring>

#include "relight/base/fixed_ops.h"
#include "surface_emitter_frame.h"
#include "surface_emitter_gather.h"
#include "surface_emitter_gather_avx2.h"
#include "surface_emitter_extrapolate.h"
#include "surface_emitter_moments.h"

namespace relight {
namespace {

// The gradient's part of the irradiance at (u, v) Q16.16 metres, Q32.
int64_t GradientTerm(int64_t gu, int64_t gv, const int32_t* uv_q16) {
  return RoundShiftSat64(static_cast<Int128>(gu) * uv_q16[0] + static_cast<Int128>(gv) * uv_q16[1],
                         -16);
}

// v / 2^shift rounded (halves up), clamped to +-limit (< 2^31): what
// RoundShiftSat64 and the clamp give, in int64 (a v within 2^(shift - 1) of
// INT64_MAX would overflow the add, and clamps to limit either way).
inline int32_t ClampedView(int64_t v, int shift, int32_t limit) {
  const int64_t half = int64_t{1} << (shift - 1);
  const int64_t r = v > INT64_MAX - half ? INT64_MAX : (v + half) >> shift;
  return static_cast<int32_t>(r > limit ? limit : (r < -limit ? -limit : r));
}

constexpr int kViewShift = kExitanceFracBits - kGatherFracBits;
// The moment view, Q20 x metres: 16 m of headroom over the exitance view.
constexpr int kMomentViewShift = kViewShift + 4;
// Moment weights before the shift t: Q36 per metre (Q36 x Q20 = Q56).
static_assert(kMomentWeightFracBits + kExitanceFracBits - kMomentViewShift == kGatherFracBits + 32,
              "moment products and factor products must both be Q56");

}  // namespace

struct HierarchySolveQ32::Sweep {
  HierarchySolveQ32* self;
  const int64_t* emitted;
  const int64_t* extra;
  int64_t* b;
  int64_t change[kEmitterSolveBlocks];
  Int128 l1[kEmitterSolveBlocks][3];  // sum over the leaves of |change|, per channel
  int64_t peak[kEmitterSolveBlocks];
  Int128 num[3], den[3];  // the extrapolation's r / (1 - r) per channel
  BlockStep step;
};

// step(sweep, block) for every block, the blocks dealt over the pool's
// threads (their nodes are disjoint: each tree is in one block).
void HierarchySolveQ32::RunOnBlocks(WorkerPool* pool, Sweep* sweep, BlockStep step) {
  sweep->step = step;
  const auto task = [](void* context, int thread) {
    Sweep* s = static_cast<Sweep*>(context);
    for (int block = thread; block < kEmitterSolveBlocks; block += s->self->threads_) (s->self->*(s->step))(s, block);
  };
  if (threads_ > 1) {
    pool->Run(task, sweep);
  } else {
    task(sweep, 0);
  }
}

Status HierarchySolveQ32::Init(const Bake& bake) {
  if (!bake.hierarchy) return Status(StatusCode::kUnsupported, "bake has no hierarchy");
  h_ = &*bake.hierarchy;
  const BakeHierarchy& h = *h_;
  const uint32_t n = h.node_count();
  BuildGatherLists();

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
  AssignBlocks();
  g0_.assign(size_t{n} * 3, 0);
  gu_.assign(size_t{n} * 3, 0);
  gv_.assign(size_t{n} * 3, 0);
  delta_.assign(size_t{n} * 3, 0);
  mu_.assign(size_t{n} * 3, 0);
  mv_.assign(size_t{n} * 3, 0);
  dirty_.assign(n, 0);
  dirty_list_.assign(n, 0);
  last_result_ = near_previous_ = nullptr;
  for (std::vector<int32_t>& v : view_) v.assign(size_t{n} * 4, 0);
  // Rows of 64 bytes on 64-byte boundaries: an inner source's gather reads one cache line.
  for (int k = 0; k < kEmitterSolveBlocks; ++k) {
    inner_rows_[k].assign(size_t{moments_.inner_before[n]} * kInnerRowInts + kInnerRowInts, 0);
    const auto address = reinterpret_cast<uintptr_t>(inner_rows_[k].data());
    inner_row_[k] = inner_rows_[k].data() + ((64 - address % 64) % 64) / sizeof(int32_t);
  }
  moment_entries_ = moments_.entries.size();
  moments_.entries = {};  // in inner_gather_ now
  return Status::Ok();
}

int32_t HierarchySolveQ32::ToView(int64_t b_q32) const { return ClampedView(b_q32, kViewShift, view_limit_); }

void HierarchySolveQ32::AddMomentSum(const int64_t m[3], int64_t a[3]) const {
  // Q(56 - t) x 2^t = Q56; Init's bound keeps a + this below 2^63
  // (saturating all the same: a hostile bake must not reach overflow).
  const Int128 scale = Int128{1} << moments_.shift;
  for (int ch = 0; ch < 3; ++ch) a[ch] = AddSat64(a[ch], SaturateI64(static_cast<Int128>(m[ch]) * scale));
}

int32_t HierarchySolveQ32::ToMomentView(int64_t m_q32) const {
  return ClampedView(m_q32, kMomentViewShift, view_limit_);
}

void HierarchySolveQ32::SetView(uint32_t k, const int64_t* b, int32_t* view, int32_t* rows) const {
  for (int ch = 0; ch < 3; ++ch) view[4 * size_t{k} + ch] = ToView(b[3 * size_t{k} + ch]);
  if (h_->leaf(k)) return;
  int32_t* row = &rows[kInnerRowInts * size_t{moments_.inner_before[k]}];
  for (int ch = 0; ch < 3; ++ch) {
    row[ch] = view[4 * size_t{k} + ch];
    row[4 + ch] = ToMomentView(mu_[3 * size_t{k} + ch]);
    row[8 + ch] = ToMomentView(mv_[3 * size_t{k} + ch]);
  }
}

void HierarchySolveQ32::ViewBlock(Sweep* sweep, int block) {
  int64_t* b = sweep->b;
  for (const uint32_t r : block_runs_[block]) {
    const uint32_t begin = run_begin_[r], end = run_begin_[r + 1];
    Pull(begin, end, b, view_[0].data(), inner_row_[0]);
    for (uint32_t k = begin; k < end; ++k)
      if (h_->leaf(k)) SetView(k, b, view_[0].data(), inner_row_[0]);
  }
}

void HierarchySolveQ32::AddEmitted(const int64_t* emitted_q32, int64_t* b) {
  const BakeHierarchy& h = *h_;
  const uint32_t n = node_count();
  int32_t* view = view_[0].data();
  // On the last solve's result every inner node holds the pull of its
  // leaves, so only the emitting leaves' ancestors need pulling: the same
  // bits as the whole pull, which any other array takes.
  const bool sparse = b == last_result_ && near_previous_ == nullptr;
  uint32_t dirty = 0;
  for (uint32_t k = 0; k < n; ++k) {
    if (!h.leaf(k) || (sparse && emitted_q32[k] == 0)) continue;
    for (int ch = 0; ch < 3; ++ch) {
      const size_t i = 3 * size_t{k} + ch;
      b[i] = AddSat64(b[i], emitted_q32[k]);
      view[4 * size_t{k} + ch] = ToView(b[i]);
    }
    if (sparse) MarkAncestors(k, &dirty);
  }
  if (sparse) {
    PullMarked(dirty, b);
    return;  // b is still the last result, now with its emitter
  }
  last_result_ = nullptr;
  for (size_t r = 0; r + 1 < run_begin_.size(); ++r)
    Pull(run_begin_[r], run_begin_[r + 1], b, view, inner_row_[0]);
}

void HierarchySolveQ32::ReflectedStart(const int64_t* e, int64_t* b) const {
  const BakeHierarchy& h = *h_;
  for (uint32_t k = 0; k < node_count(); ++k)
    for (int ch = 0; ch < 3; ++ch) {
      const size_t i = 3 * size_t{k} + ch;
      b[i] = h.leaf(k) ? RoundShiftSat64(static_cast<Int128>(rho_q32_[i]) * e[i], -32) : 0;
    }
}

int64_t HierarchySolveQ32::ReflectedChange(uint32_t k, int ch, int64_t shot_now, int64_t shot_before) const {
  return RoundShiftSat64(static_cast<Int128>(rho_q32_[3 * size_t{k} + ch]) * SubSat64(shot_now, shot_before), -32);
}

void HierarchySolveQ32::EmittedAndReflectedStart(const int64_t* emitted, const int64_t* shot, int64_t* b) const {
  const BakeHierarchy& h = *h_;
  for (uint32_t k = 0; k < node_count(); ++k)
    for (int ch = 0; ch < 3; ++ch) {
      const size_t i = 3 * size_t{k} + ch;
      b[i] = h.leaf(k) ? AddSat64(RoundShiftSat64(static_cast<Int128>(rho_q32_[i]) * shot[k], -32), emitted[k]) : 0;
    }
}

void HierarchySolveQ32::SweepBlock(Sweep* sweep, int block) {
  const BakeHierarchy& h = *h_;
  int32_t* view = view_[block].data();
  int32_t* rows = inner_row_[block];
  int64_t* b = sweep->b;
  int64_t change = 0, peak = 0;
  Int128 l1[3] = {0, 0, 0};
  for (const uint32_t r : block_runs_[block]) {
    const uint32_t begin = run_begin_[r], end = run_begin_[r + 1];
    for (uint32_t k = begin; k < end; ++k) {  // gather
      const EmitterGatherEntry* e = gather_.data() + gather_offsets_[k];  // data(): may be empty
      const uint32_t count = gather_offsets_[k + 1] - gather_offsets_[k];
      int64_t* g0 = &g0_[3 * size_t{k}];
      int64_t* gu = &gu_[3 * size_t{k}];
      int64_t* gv = &gv_[3 * size_t{k}];
      int64_t a[3], u[3], v[3];
      const EmitterInnerSourceEntry* ie = inner_gather_.data() + inner_offsets_[k];  // data(): may be empty
      const uint32_t inner_count = inner_offsets_[k + 1] - inner_offsets_[k];
      int64_t m[3];
      if (h.leaf(k)) {  // a leaf's links carry no gradient
        if (vector_) {
          GatherLeafAvx2(e, count, view, a);
          if (inner_count != 0) GatherLeafFromInnerAvx2(ie, inner_count, rows, a, m);
        } else {
          GatherLeaf(e, count, view, a);
          if (inner_count != 0) GatherLeafFromInner(ie, inner_count, rows, a, m);
        }
        if (inner_count != 0) AddMomentSum(m, a);
        for (int ch = 0; ch < 3; ++ch) {
          g0[ch] = RoundShiftSat64(a[ch], -kGatherFracBits);
          gu[ch] = gv[ch] = 0;
        }
        continue;
      }
      const int32_t* g = gradient_.data() + 2 * size_t{gradient_offsets_[k]};  // empty when no inner node gathers
      const int32_t* ig = g + 2 * size_t{count};  // the inner sources' gradients follow the leaves'
      if (vector_) {
        GatherInnerAvx2(e, g, count, view, a, u, v);
        if (inner_count != 0) GatherInnerFromInnerAvx2(ie, ig, inner_count, rows, a, u, v, m);
      } else {
        GatherInner(e, g, count, view, a, u, v);
        if (inner_count != 0) GatherInnerFromInner(ie, ig, inner_count, rows, a, u, v, m);
      }
      if (inner_count != 0) AddMomentSum(m, a);
      constexpr int kGradientShift = kBakeGradientFracBits + kGatherFracBits - kExitanceFracBits;
      for (int ch = 0; ch < 3; ++ch) {
        gu[ch] = RoundShiftSat64(u[ch], -kGradientShift);
        gv[ch] = RoundShiftSat64(v[ch], -kGradientShift);
        // About the surface's origin, so a child adds it as it is.
        g0[ch] = SubSat64(RoundShiftSat64(a[ch], -kGatherFracBits),
                          GradientTerm(gu[ch], gv[ch], &centre_uv_q16_[2 * size_t{k}]));
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
    const int64_t* extra = sweep->extra;
    for (uint32_t k = begin; k < end; ++k) {
      if (!h.leaf(k)) continue;
      for (int ch = 0; ch < 3; ++ch) {
        const size_t i = 3 * size_t{k} + ch;
        // Saturating: a bake whose links pass validation cannot make these
        // overflow, but a runaway solve must not reach signed overflow either.
        int64_t e = AddSat64(g0_[i], GradientTerm(gu_[i], gv_[i], &centre_uv_q16_[2 * size_t{k}]));
        if (extra != nullptr) e = AddSat64(e, extra[i]);
        const int64_t updated =
            AddSat64(sweep->emitted[k], RoundShiftSat64(static_cast<Int128>(rho_q32_[i]) * e, -32));
        delta_[i] = SubSat64(updated, b[i]);
        const int64_t d = SaturateI64(updated > b[i] ? Int128{updated} - b[i] : Int128{b[i]} - updated);
        if (d > change) change = d;
        l1[ch] += d;
        if (updated > peak) peak = updated;
        b[i] = updated;
        view[4 * size_t{k} + ch] = ToView(updated);
      }
    }
    Pull(begin, end, b, view, rows);
  }
  sweep->change[block] = change;
  for (int ch = 0; ch < 3; ++ch) sweep->l1[block][ch] = l1[ch];
  sweep->peak[block] = peak;
}

int HierarchySolveQ32::SolveRgb(const int64_t* emitted_q32, const int64_t* extra_irradiance_q32,
                                int64_t* b, WorkerPool* pool, int64_t peak_floor_q32, const SweepContraction* hint,
                                SweepContraction* seen, int max_sweeps) {
  const SweepContraction given = hint != nullptr ? *hint : SweepContraction{};  // seen may be the hint
  hint = &given;
  if (seen != nullptr) *seen = SweepContraction{};
  const uint32_t n = node_count();
  threads_ = pool != nullptr ? pool->threads() : 1;
  Sweep sweep{this, emitted_q32, extra_irradiance_q32, b, {}, {}, {}, {}, {}, nullptr};
  // A few changed leaves (an FE move's edges): their ancestors alone. When
  // most leaves changed (an AR move's first shot reaches every leaf), the
  // whole pull on both threads is cheaper (0.98 -> 0.74 ms on the 16k room's
  // AR move); both give the same bits.
  if (near_previous_ != nullptr && near_previous_ == last_result_ && near_count_ <= n / kSparseSetUpShare) {
    ViewChangedLeaves(b);
  } else {
    RunOnBlocks(pool, &sweep, &HierarchySolveQ32::ViewBlock);
  }
  near_previous_ = nullptr;
  last_result_ = b;
  for (int k = 1; k < kEmitterSolveBlocks; ++k) {
    std::memcpy(view_[k].data(), view_[0].data(), size_t{n} * 4 * sizeof(int32_t));
    std::memcpy(inner_row_[k], inner_row_[0], size_t{moments_.inner_before[n]} * kInnerRowInts * sizeof(int32_t));
  }
  Int128 l1_prev[3] = {0, 0, 0};
  int64_t previous = 0;
  int sweep_count = 0;
  while (sweep_count < max_sweeps) {
    ++sweep_count;
    RunOnBlocks(pool, &sweep, &HierarchySolveQ32::SweepBlock);
    // Every block's nodes into every other block's view, for the next sweep.
    for (int from = 0; from < kEmitterSolveBlocks; ++from) {
      for (const uint32_t r : block_runs_[from]) {
        const size_t lo = 4 * size_t{run_begin_[r]}, hi = 4 * size_t{run_begin_[r + 1]};
        const size_t mlo = kInnerRowInts * size_t{moments_.inner_before[run_begin_[r]]};
        const size_t mhi = kInnerRowInts * size_t{moments_.inner_before[run_begin_[r + 1]]};
        for (int to = 0; to < kEmitterSolveBlocks; ++to) {
          if (to == from) continue;
          std::memcpy(&view_[to][lo], &view_[from][lo], (hi - lo) * sizeof(int32_t));
          std::memcpy(inner_row_[to] + mlo, inner_row_[from] + mlo, (mhi - mlo) * sizeof(int32_t));
        }
      }
    }
    int64_t change = 0, peak = peak_floor_q32;
    Int128 l1[3] = {0, 0, 0};
    for (int k = 0; k < kEmitterSolveBlocks; ++k) {
      if (sweep.change[k] > change) change = sweep.change[k];
      if (sweep.peak[k] > peak) peak = sweep.peak[k];
      for (int ch = 0; ch < 3; ++ch) l1[ch] += sweep.l1[k][ch];
    }
    if (seen != nullptr && sweep_count <= 2) {
      seen->change[sweep_count - 1] = change;
      for (int ch = 0; ch < 3; ++ch) seen->l1[sweep_count - 1][ch] = l1[ch];
      seen->valid = sweep_count == 2 && change < seen->change[0];
    }
    if (change == 0) break;
    if (sweep_count == 1 && hint->valid && hint->reused < kMaxContractionReuse &&
        change < (int64_t{1} << 55) && FirstSweepSuffices(change, peak, *hint, kEmitterSolveToleranceLog2)) {
      if (seen != nullptr) {
        *seen = *hint;
        ++seen->reused;
      }
      ExtrapolationRatios(hint->l1[1], hint->l1[0], sweep.num, sweep.den);
      if (sweep.num[0] != 0 || sweep.num[1] != 0 || sweep.num[2] != 0)
        RunOnBlocks(pool, &sweep, &HierarchySolveQ32::ExtrapolateBlock);
      break;
    }
    // change >= 2^55 would overflow the 128-bit test below; such a solve is
    // far from converged anyway.
    if (sweep_count >= 2 && change < previous && change < (int64_t{1} << 55)) {
      // Remaining ~ change r / (1 - r), r = change / previous, capped at 0.99.
      const Int128 lhs = static_cast<Int128>(change) << kEmitterSolveToleranceLog2;
      const bool capped = Int128{change} * 100 >= Int128{previous} * 99;
      const bool done = capped ? lhs * 99 < peak
                               : lhs * change < static_cast<Int128>(peak) * (previous - change);
      if (done) {
        ExtrapolationRatios(l1, l1_prev, sweep.num, sweep.den);
        if (sweep.num[0] != 0 || sweep.num[1] != 0 || sweep.num[2] != 0)
          RunOnBlocks(pool, &sweep, &HierarchySolveQ32::ExtrapolateBlock);
        break;
      }
    }
    previous = change;
    for (int ch = 0; ch < 3; ++ch) l1_prev[ch] = l1[ch];
  }
  return sweep_count;
}

// The rest of the series on a block's leaves (surface_emitter_extrapolate.h),
// then its inner nodes and view from them.
void HierarchySolveQ32::ExtrapolateBlock(Sweep* sweep, int block) {
  for (const uint32_t r : block_runs_[block]) {
    const uint32_t begin = run_begin_[r], end = run_begin_[r + 1];
    ExtrapolateLeaves(end - begin, h_->node_child_count.data() + begin, delta_.data() + 3 * size_t{begin},
                      sweep->num, sweep->den, sweep->b + 3 * size_t{begin});
  }
  ViewBlock(sweep, block);
}

}  // namespace relight
