// Run-time emitter slots (surface_emitters.h).
//
// Scaling and overflow of AddTo: unit response Q24 (< 2^31) x luminance
// LightQ12 (< 2^31) in int64 (< 2^62), rounded to LightQ12 and added with
// int32 saturation.
#include "surface_emitters.h"

#include <utility>

#include "relight/base/fixed.h"
#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"
#include "surface_emitter_coverage.h"

namespace relight {
namespace {

Status NoHierarchy() {
  return Status(StatusCode::kUnsupported,
                "surface emitter: no radiosity hierarchy loaded (it needs a bake of --solver "
                "hierarchical without --no-hierarchy, opened with surface emitters: relightd "
                "loads the hierarchy only when its patch has an [[emitter]])");
}

}  // namespace

Status SurfaceEmitters::Open(const Bake& bake, int refine_links, int refine_bits) {
  bake_ = &bake;
  vertex_count_ = bake.mesh.vertex_count();
  supported_ = bake.hierarchy.has_value();
  if (!supported_) return Status::Ok();
  // The hierarchy's indices were checked by the engine's ValidateBake.
  RELIGHT_RETURN_IF_ERROR(solver_.Init(bake));
  RELIGHT_RETURN_IF_ERROR(refine_.Open(bake, refine_links, refine_bits));
  const BakeHierarchy& h = *bake.hierarchy;
  surface_root_.assign(bake.mesh.surface_names.size(), kBakeNoIndex);
  for (uint32_t k = 0; k < h.node_count(); ++k) {
    if (h.node_parent[k] == kBakeNoIndex && h.node_surface[k] < surface_root_.size())
      surface_root_[h.node_surface[k]] = k;
  }
  MakeVertexLeafWeights(h, vertex_count_, &vertex_weights_);
  coverage_scratch_.assign(h.node_count(), 0);
  first_shot_scratch_.assign(h.node_count(), 0);
  extra_.assign(size_t{h.node_count()} * 3, 0);
  no_emission_.assign(h.node_count(), 0);
  changed_leaves_.assign(h.node_count(), 0);
  for (Slot& s : slots_) {
    for (Solution* x : {&s.now, &s.before}) {
      x->coverage_q32.assign(h.node_count(), 0);
      x->exitance_q32.assign(size_t{h.node_count()} * 3, 0);
      x->unit_q24.assign(size_t{vertex_count_} * 3, 0);
      x->first_shot_q32.assign(h.node_count(), 0);
    }
  }
  return Status::Ok();
}

Status SurfaceEmitters::CheckSlot(int slot) const {
  if (!supported_) return NoHierarchy();
  if (slot < 0 || slot >= kMaxSurfaceEmitters) {
    return Status(StatusCode::kInvalidArgument,
                  StrFormat("surface emitter: slot %d outside 0..%d", slot, kMaxSurfaceEmitters - 1));
  }
  return Status::Ok();
}

Status SurfaceEmitters::Place(int slot, const SurfaceEmitterShape& shape, WorkerPool* pool) {
  RELIGHT_RETURN_IF_ERROR(CheckSlot(slot));
  const std::vector<std::string>& names = bake_->mesh.surface_names;
  uint32_t surface = 0;
  while (surface < names.size() && names[surface] != shape.surface) ++surface;
  if (surface == names.size() || surface_root_[surface] == kBakeNoIndex) {
    return Status(StatusCode::kNotFound,
                  StrFormat("surface emitter: no surface '%s' in the bake", shape.surface.c_str()));
  }
  for (int64_t& f : coverage_scratch_) f = 0;
  const Status st = SurfaceEmitterCoverageQ32(*bake_->hierarchy, bake_->mesh, surface_root_[surface],
                                              shape.corners_q16, shape.corner_count,
                                              coverage_scratch_.data());
  if (!st.ok()) {
    return Status(st.code(), StrFormat("%s (surface '%s')", st.message().c_str(), shape.surface.c_str()));
  }
  const bool refined = shape.method == SurfaceEmitterMethod::kAdaptiveRefine;
  if (refined) {
    RELIGHT_RETURN_IF_ERROR(refine_.FirstShot(surface_root_[surface], shape, coverage_scratch_.data(),
                                              first_shot_scratch_.data(), pool));
  }
  Slot& s = slots_[slot];
  s.moved = s.placed;
  s.placed = true;
  // The same coverage and method give the same first shot, so the same solution.
  const auto same = [&](const Solution& x) { return x.refined == refined && coverage_scratch_ == x.coverage_q32; };
  if (same(s.now)) return Status::Ok();  // where it is (or was)
  if (s.before.solved && same(s.before)) {
    std::swap(s.now, s.before);  // back where it came from: the stored bits
    s.restored = true;
    // A settled solution anchors the quick answers that start from it.
    if (s.now.settled)
      for (int a = 0; a < 3; ++a) s.anchor_q16[a] = s.now.centroid_q16[a];
    return Status::Ok();
  }
  if (s.now.solved) std::swap(s.now, s.before);  // keep the last solved one to start from
  s.now.coverage_q32.swap(coverage_scratch_);
  s.now.root = surface_root_[surface];
  for (int a = 0; a < 3; ++a) {
    int64_t sum = 0;
    for (int k = 0; k < shape.corner_count; ++k) sum += shape.corners_q16[k][a];
    s.now.centroid_q16[a] = sum / shape.corner_count;
  }
  if (refined) s.now.first_shot_q32.swap(first_shot_scratch_);
  s.now.refined = refined;
  s.now.solved = false;
  return Status::Ok();
}

Status SurfaceEmitters::SetLuminance(int slot, const LightQ12 rgb[3]) {
  RELIGHT_RETURN_IF_ERROR(CheckSlot(slot));
  for (int c = 0; c < 3; ++c) {
    if (rgb[c].raw() < 0) return Status(StatusCode::kInvalidArgument, "surface emitter: luminance < 0");
  }
  for (int c = 0; c < 3; ++c) slots_[slot].luminance_q12[c] = rgb[c].raw();
  return Status::Ok();
}

Status SurfaceEmitters::Remove(int slot) {
  RELIGHT_RETURN_IF_ERROR(CheckSlot(slot));
  slots_[slot].placed = false;  // its solution stays for a placement back there
  return Status::Ok();
}

// A move starts from the previous solution when its emitted flux is
// within a factor 2 of the new one: the start's error is then the difference
// of two similar indirect fields (a drag: mostly the near field), against
// the whole indirect field from the emission alone. A new light (placed
// where nothing was, or after a remove) starts from its emission (and
// SolvePending then adds its first bounce and the later-bounce table).
void SurfaceEmitters::StartFrom(const Slot& s, int64_t* b, bool* warm) {
  const BakeHierarchy& h = *bake_->hierarchy;
  const uint32_t n = h.node_count();
  const int64_t* now = s.now.coverage_q32.data();
  const int64_t* before = s.before.coverage_q32.data();
  const bool moved = s.moved && s.before.solved;  // else no flux to compare
  Int128 flux_before = 0, flux_now = 0;  // covered area, Q64 m^2
  for (uint32_t k = 0; k < n && moved; ++k) {
    if (!h.leaf(k)) continue;
    const Int128 area = static_cast<Int128>(h.node_area[k]);
    flux_before += area * before[k];
    flux_now += area * now[k];
  }
  *warm = moved && flux_before <= 2 * flux_now && flux_now <= 2 * flux_before;
  if (*warm) {
    // The previous solution with the new emission in place of the old, so
    // the first sweep's change is light, not the step in emission (the
    // stopping rule reads the sweeps' changes as a contraction).
    for (uint32_t k = 0; k < n; ++k)
      for (int c = 0; c < 3; ++c) {
        const size_t i = 3 * size_t{k} + c;
        // Adaptive refine solves without its emitter's exitance (added after).
        const int64_t emitted = s.now.refined ? 0 : now[k];
        b[i] = h.leaf(k) ? AddSat64(s.before.exitance_q32[i], emitted - before[k]) : s.before.exitance_q32[i];
      }
    // An adaptive-refine move from an adaptive-refine solution also knows
    // how its first bounce changed (the two first shots), so the start
    // takes that in too: the first sweep's change is then the later bounces'
    // alone and the sweeps stop sooner (the paper's room: see
    // docs/hierarchy.md "AR moves start one bounce ahead").
    const bool shots = s.now.refined && s.before.refined;
    // The leaves whose start differs from the previous solution, for the
    // solver's StartNear.
    changed_count_ = 0;
    for (uint32_t k = 0; k < n; ++k) {
      if (!h.leaf(k)) continue;
      bool changed = (s.now.refined ? 0 : now[k]) != before[k];
      if (shots && s.now.first_shot_q32[k] != s.before.first_shot_q32[k]) {
        for (int c = 0; c < 3; ++c)
          b[3 * size_t{k} + c] = AddSat64(
              b[3 * size_t{k} + c], solver_.ReflectedChange(k, c, s.now.first_shot_q32[k], s.before.first_shot_q32[k]));
        changed = true;
      }
      if (changed) changed_leaves_[changed_count_++] = k;
    }
    return;
  }
  for (uint32_t k = 0; k < n; ++k)  // the solver pulls the inner nodes up
    for (int c = 0; c < 3; ++c) b[3 * size_t{k} + c] = h.leaf(k) && !s.now.refined ? now[k] : 0;
}

int SurfaceEmitters::SolvePending(WorkerPool* pool) {
  int solved = 0;
  last_sweeps_ = 0;
  last_warm_ = 0;
  last_quick_ = 0;
  for (int slot = 0; slot < kMaxSurfaceEmitters; ++slot) {
    Slot& s = slots_[slot];
    if (s.placed && s.now.solved && s.restored && observer_ != nullptr) {
      observer_->OnSolved(slot, s.now.exitance_q32.data());
    }
    s.restored = false;
    if (!s.placed || s.now.solved) continue;
    bool warm = false;
    int64_t* b = s.now.exitance_q32.data();
    StartFrom(s, b, &warm);
    last_warm_ += warm ? 1 : 0;
    // A move starts where the last solve left off: the slot's last move
    // says how fast its sweeps will contract. A new light leaves no hint;
    // it takes the one of the table's source it covers most (below).
    if (!warm || s.drag_refined != s.now.refined) s.drag = SweepContraction{};
    const SweepContraction* hint = warm ? &s.drag : nullptr;
    SweepContraction* seen = warm ? &s.drag : nullptr;
    s.drag_refined = s.now.refined;
    // Answer now, settle later (surface_emitters.h): only from a start that
    // holds every bounce, near where the slot was last solved in full.
    const bool may_answer =
        quick_changes_ && bounces_.source_count() > 0 && NearAnchor(s);
    bool quick = false;
    if (s.now.refined) {
      // AR: the emitter's light reaches the leaves as the first shot; the
      // solve interreflects it, stopping against the emitter's own unit
      // exitance, and the emitter's exitance is added after.
      FillExtra(s.now);
      if (warm) {
        // StartFrom took in the change of first bounce; the table gives the
        // change of the later ones. The set-up then pulls every node (the
        // table's change reaches leaves StartNear's list does not hold).
        quick = may_answer && s.before.refined;
        if (quick) {
          bounces_.AddChange(s.now.coverage_q32.data(), s.now.root, s.before.coverage_q32.data(), s.before.root, b);
        } else {
          solver_.StartNear(s.before.exitance_q32.data(), changed_leaves_.data(), changed_count_);
        }
      } else {
        // A new light is solved at once: the table alone is too far off for
        // the grids, lit mostly by later bounces (the Cornell box's ceiling
        // panel after no sweep: floor grid 0.46 % of peak mean, bar 0.2 %).
        solver_.ReflectedStart(extra_.data(), b);
        hint = bounces_.AddTo(s.now.coverage_q32.data(), s.now.root, b);
      }
    } else {
      if (warm) {
        solver_.StartNear(s.before.exitance_q32.data(), changed_leaves_.data(), changed_count_);
      } else if (FirstBounceStart(s.now.root, s.now.coverage_q32.data(), b, pool)) {
        // Solved at once too: FE's start is further off still (a closed
        // box's 4-corner place 1.2 % of peak max after no sweep).
        hint = bounces_.AddTo(s.now.coverage_q32.data(), s.now.root, b);
      }
    }
    // A quick answer leaves the slot's drag hint to its next full solve.
    last_sweeps_ += quick ? SolveSlot(slot, nullptr, nullptr, pool, 0)
                          : SolveSlot(slot, hint, seen, pool, kEmitterSolveMaxSweeps);
    last_quick_ += quick ? 1 : 0;
    ++solved;
  }
  return solved;
}

void SurfaceEmitters::FillExtra(const Solution& x) {
  for (uint32_t k = 0; k < solver_.node_count(); ++k)
    for (int c = 0; c < 3; ++c) extra_[3 * size_t{k} + c] = x.first_shot_q32[k];
}

int SurfaceEmitters::SolveSlot(int slot, const SweepContraction* hint, SweepContraction* seen, WorkerPool* pool,
                               int max_sweeps) {
  Slot& s = slots_[slot];
  int64_t* b = s.now.exitance_q32.data();
  int sweeps = 0;
  if (s.now.refined) {
    sweeps = solver_.SolveRgb(no_emission_.data(), extra_.data(), b, pool, int64_t{1} << kCoverageFracBits, hint,
                              seen, max_sweeps);
    solver_.AddEmitted(s.now.coverage_q32.data(), b);
  } else {
    sweeps = solver_.SolveRgb(s.now.coverage_q32.data(), nullptr, b, pool, 0, hint, seen, max_sweeps);
  }
  s.now.settled = max_sweeps > 0;
  if (s.now.settled)
    for (int a = 0; a < 3; ++a) s.anchor_q16[a] = s.now.centroid_q16[a];
  SpreadSolution(slot, pool);
  s.now.solved = true;
  return sweeps;
}

int SurfaceEmitters::Settle(WorkerPool* pool) {
  int settled = 0;
  last_sweeps_ = 0;
  last_quick_ = 0;
  for (int slot = 0; slot < kMaxSurfaceEmitters; ++slot) {
    Slot& s = slots_[slot];
    if (!s.placed || !s.now.solved || s.now.settled) continue;
    if (s.now.refined) {
      // An AR answer holds its emitter's own exitance, which its solve leaves out.
      const BakeHierarchy& h = *bake_->hierarchy;
      for (uint32_t k = 0; k < h.node_count(); ++k) {
        if (!h.leaf(k)) continue;
        for (int c = 0; c < 3; ++c)
          s.now.exitance_q32[3 * size_t{k} + c] = SubSat64(s.now.exitance_q32[3 * size_t{k} + c], s.now.coverage_q32[k]);
      }
      FillExtra(s.now);
    }
    last_sweeps_ += SolveSlot(slot, nullptr, nullptr, pool, kEmitterSolveMaxSweeps);
    ++settled;
  }
  return settled;
}

bool SurfaceEmitters::NearAnchor(const Slot& s) const {
  // |d|^2 (Q32 m^2; corners are within +-2^31 Q16, so each square < 2^64
  // is taken as Int128) x 4^reach <= the source area.
  Int128 d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const Int128 d = Int128{s.now.centroid_q16[a]} - s.anchor_q16[a];
    d2 += d * d;
  }
  return (d2 << (2 * kQuickReachLog2)) <= static_cast<Int128>(bounces_.source_area_q32());
}

int32_t SurfaceEmitters::quick_reach_q16() const {
  if (!quick_changes_) return 0;  // sqrt(Q32 m^2) = Q16 m
  return static_cast<int32_t>(ISqrt64(static_cast<uint64_t>(bounces_.source_area_q32())) >> kQuickReachLog2);
}

bool SurfaceEmitters::settled() const {
  for (const Slot& s : slots_) {
    if (s.placed && s.now.solved && !s.now.settled) return false;
  }
  return true;
}

// A slot's new solution to the grids (the observer) and to the vertices: two
// independent reads of it, one on each thread when there are two.
void SurfaceEmitters::SpreadSolution(int slot, WorkerPool* pool) {
  struct Spread {
    SurfaceEmitters* self;
    int slot;
    int threads;
  } spread{this, slot, pool != nullptr ? pool->threads() : 1};
  const auto task = [](void* context, int thread) {
    const Spread* sp = static_cast<const Spread*>(context);
    SurfaceEmitters* self = sp->self;
    Slot& s = self->slots_[sp->slot];
    if (thread == 0 && self->observer_ != nullptr) self->observer_->OnSolved(sp->slot, s.now.exitance_q32.data());
    if (thread == (sp->threads > 1 ? 1 : 0)) {
      // Unit luminance L = 1 cd/m^2 emits M = pi L; the vertex luminance is
      // exitance / pi, so the pi cancels: the unit-coverage solve is the answer.
      LeavesToVerticesQ24(self->vertex_weights_, self->vertex_count_, self->solver_.exitance_q24(),
                          s.now.unit_q24.data());
    }
  };
  if (spread.threads > 1) {
    pool->Run(task, &spread);
  } else {
    task(&spread, 0);
  }
}

// A new fractional-emissivity light starts as adaptive refine's does: the
// emitter's first bounce from its own links (no sweep over every link), plus
// its emission; the table's later bounces go on top. If the shot cannot be
// made (no tree, or one deeper than the walk allows) the start stays the
// emission alone, without the table.
bool SurfaceEmitters::FirstBounceStart(uint32_t root, const int64_t* coverage_q32, int64_t* b, WorkerPool* pool) {
  if (root == kBakeNoIndex || !refine_.FractionalFirstShot(root, coverage_q32, first_shot_scratch_.data(), pool).ok())
    return false;
  solver_.EmittedAndReflectedStart(coverage_q32, first_shot_scratch_.data(), b);
  return true;
}

// Each coarse source lit alone, as a new FE light covering it is solved;
// what the sweeps added to its start is its later bounces. The slots' arrays
// are free here (nothing is placed yet), so slot 0's serve as scratch.
void SurfaceEmitters::PrecomputeBounces(int64_t budget_bytes, WorkerPool* pool) {
  if (!supported_) return;
  const BakeHierarchy& h = *bake_->hierarchy;
  const int64_t entries = static_cast<int64_t>(solver_.sweep_entries()) + 1;
  const int64_t sources = kBounceTableWork / entries;
  bounces_.Partition(h, budget_bytes, static_cast<uint32_t>(sources > UINT32_MAX ? UINT32_MAX : sources));
  int64_t* coverage = slots_[0].now.coverage_q32.data();
  int64_t* b = slots_[0].now.exitance_q32.data();
  int64_t* start = slots_[0].before.exitance_q32.data();
  const size_t values = size_t{h.node_count()} * 3;
  for (uint32_t j = 0; j < bounces_.source_count(); ++j) {
    bounces_.UnitCoverage(j, coverage);
    const uint32_t root = surface_root_[h.node_surface[bounces_.source_node(j)]];
    if (!FirstBounceStart(root, coverage, b, pool)) continue;  // its table stays 0
    for (size_t i = 0; i < values; ++i) start[i] = b[i];
    SweepContraction seen;
    solver_.SolveRgb(coverage, nullptr, b, pool, 0, nullptr, &seen);
    bounces_.Store(j, b, start, seen);
  }
  for (Solution* x : {&slots_[0].now, &slots_[0].before}) {
    for (int64_t& v : x->coverage_q32) v = 0;
    for (int64_t& v : x->exitance_q32) v = 0;
  }
}

void SurfaceEmitters::AddTo(int32_t* vertex_q12) const {
  for (const Slot& s : slots_) {
    if (!s.placed || !s.now.solved) continue;
    if (s.luminance_q12[0] == 0 && s.luminance_q12[1] == 0 && s.luminance_q12[2] == 0) continue;
    const size_t n = size_t{vertex_count_} * 3;
    for (size_t i = 0; i < n; ++i) {
      const int64_t add = (int64_t{s.now.unit_q24[i]} * s.luminance_q12[i % 3] + (int64_t{1} << 23)) >> 24;
      vertex_q12[i] = SaturateI32(int64_t{vertex_q12[i]} + add);
    }
  }
}

}  // namespace relight
