// The engine's run-time emitter slots (relight/surface_emitter.h): per slot
// the emitter's coverage of its surface (placed once per geometry), its
// solved light per unit luminance at every vertex, per channel, and its
// luminance. A luminance change only rescales the solved light (the solve is
// linear), so it costs one multiply-add per vertex and channel.
//
// Incremental (issue 15): a slot keeps its solution per node, so a move
// re-solves starting from where the emitter was (the sweeps then only carry
// the difference of emission), and it keeps the solution before the last
// move, so moving back (or placing again what was removed) restores the
// stored bits without a solve. Each slot's light is stored apart and the mix
// is rebuilt from them, so removing one returns the others' bits exactly.
//
// Open() allocates; everything after is integer-only and allocation-free
// except the text of error messages. Not thread-safe.
#pragma once

#include <cstdint>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/base/fixed.h"
#include "relight/base/status.h"
#include "relight/engine/surface_emitter.h"
#include "surface_emitter_bounces.h"
#include "surface_emitter_refine.h"
#include "surface_emitter_solve.h"
#include "surface_emitter_vertices.h"
#include "relight/base/worker_pool.h"

namespace relight {

// Told of each slot's solve (emitter_grids.h lights the grids from it).
class EmitterSolveObserver {
 public:
  virtual ~EmitterSolveObserver() = default;
  // exitance_q32: 3 per node for unit emission, valid during the call only.
  virtual void OnSolved(int slot, const int64_t* exitance_q32) = 0;
};

class SurfaceEmitters {
 public:
  // A bake without a hierarchy opens fine; every call then returns
  // kUnsupported. refine_links: the adaptive-refine pool (new links).
  Status Open(const Bake& bake, int refine_links = kDefaultSurfaceEmitterRefineLinks,
              int refine_bits = kDefaultSurfaceEmitterRefineBits);
  // After Open: tabulates the later bounces of coarse sources
  // (surface_emitter_bounces.h) in at most budget_bytes (<= 0: none), one
  // solve per source on `pool` (may be null). New lights start from it.
  void PrecomputeBounces(int64_t budget_bytes, WorkerPool* pool);
  const EmitterBounceTable& bounces() const { return bounces_; }

  // Clips the shape against its surface and stores the coverage; the solve
  // runs at the next SolvePending(). kUnsupported (no hierarchy), kNotFound
  // (no surface of that name), kInvalidArgument (slot, or the shape: off the
  // plane, not convex, not on the surface), kOutOfRange (adaptive refine
  // needs more new links than its pool holds). On error nothing changes.
  // Adaptive refine's first shot runs on `pool` (may be null: this thread).
  Status Place(int slot, const SurfaceEmitterShape& shape, WorkerPool* pool);
  // LightQ12 cd/m^2 per channel, >= 0. kInvalidArgument for a bad slot or value.
  Status SetLuminance(int slot, const LightQ12 rgb[3]);
  Status Remove(int slot);

  // Solves every placed slot whose geometry changed, the sweeps on `pool`
  // (may be null: this thread); returns how many.
  //
  // Answer now, settle later (with quick_changes and a later-bounce table):
  // an adaptive-refine move from an adaptive-refine solution starts from
  // every bounce (the previous solution, the exact change of emission and of
  // first bounce, the table's change of later bounces) and takes that start
  // as its answer without a sweep; the slot is left unsettled. Only near
  // where the slot was last solved in full (its centroid within 1/32 of a
  // table source's side, kQuickReachLog2): the table resolves no finer, and
  // further off the calculation grids drift. The 16k-patch living room's
  // floor grid under a 1 m^2 ceiling panel moved 10 cm (1/10 of the side):
  // 0.38 % of peak mean against the float64 reference, 0.09 % solved in
  // full (bar 0.2 %); the Cornell box's panel 0.14 % at 1/8 of the side,
  // 0.24 % at 1/4. New lights are solved at once (the table alone is too
  // far off on the grids: Cornell 0.46 %). A drag of quick answers
  // does not drift: each start is the last answer plus exact differences,
  // so the k-th is the anchor's solution plus the differences from the
  // anchor to here, whatever the path. Settle() solves the unsettled ones.
  int SolvePending(WorkerPool* pool);
  // Solves every unsettled slot in full from where it is (an idle frame's
  // work); returns how many. The answer is then a full solve's.
  int Settle(WorkerPool* pool);
  bool settled() const;
  int32_t quick_reach_q16() const;  // Q16 m
  void set_quick_changes(bool on) { quick_changes_ = on; }
  static constexpr int kQuickReachLog2 = 5;
  // Adds every placed emitter's light to LightQ12 vertex luminance (3 per vertex).
  void AddTo(int32_t* vertex_q12) const;

  int last_sweeps() const { return last_sweeps_; }
  // Changes of the last SolvePending answered without a sweep (unsettled).
  int last_quick() const { return last_quick_; }
  // Solves of the last SolvePending that started from the previous solution.
  int last_warm_starts() const { return last_warm_; }
  int last_refine_links() const { return refine_.last_links(); }
  // Null or an observer that outlives this; called from SolvePending() for
  // every slot whose solution changed (solved, or restored by a move back).
  void set_observer(EmitterSolveObserver* observer) { observer_ = observer; }
  // The slot's luminance (3 x LightQ12) if it is placed and solved, else null.
  const int32_t* solved_luminance_q12(int slot) const {
    const Slot& s = slots_[slot];
    return s.placed && s.now.solved ? s.luminance_q12 : nullptr;
  }

 private:
  struct Solution {
    bool solved = false;                // exitance and unit_q24 are for coverage_q32
    std::vector<int64_t> coverage_q32;  // per node, covered fraction of each leaf
    std::vector<int64_t> exitance_q32;  // 3 per node, per unit luminance
    std::vector<int32_t> unit_q24;      // 3 per vertex
    bool settled = true;                // a full solve's answer, not a start taken as one
    bool refined = false;               // adaptive refine: first_shot_q32 holds its direct light
    std::vector<int64_t> first_shot_q32;  // per node (leaves), AR only
    uint32_t root = kBakeNoIndex;       // the emitter's surface's tree
    int64_t centroid_q16[3] = {0, 0, 0};  // of the polygon's corners, m
    // exitance_q32 of an AR solution includes the emitter's own exitance
    // (coverage), added after the solve.
  };
  struct Slot {
    bool placed = false;
    bool moved = false;  // the last Place found it placed: a move, not a new light
    bool restored = false;  // `now` came back without a solve: the observer is yet to see it
    int32_t luminance_q12[3] = {0, 0, 0};
    Solution now, before;  // before: the last solved placement the slot moved from
    // The contraction of the slot's last solve from a nearby start (a move),
    // and whether it was adaptive refine's: the next move's hint.
    SweepContraction drag;
    bool drag_refined = false;
    int64_t anchor_q16[3] = {0, 0, 0};  // the centroid of the last full solve
  };
  Status CheckSlot(int slot) const;
  void SpreadSolution(int slot, WorkerPool* pool);
  // b = the emission (coverage) plus its first bounce from the emitter's own
  // links, inner nodes 0; false (b untouched) if the shot cannot be made.
  bool FirstBounceStart(uint32_t root, const int64_t* coverage_q32, int64_t* b, WorkerPool* pool);
  void StartFrom(const Slot& s, int64_t* exitance_q32, bool* warm);
  // Solves the slot from the start in its now.exitance_q32 (StartFrom's, or
  // its own answer when settling) in at most max_sweeps (0: the start is the
  // answer, unsettled), spreads it to the vertices and grids; the sweeps.
  int SolveSlot(int slot, const SweepContraction* hint, SweepContraction* seen, WorkerPool* pool, int max_sweeps);
  // extra_ = the first shot of x in every channel (adaptive refine's solve).
  void FillExtra(const Solution& x);
  // The slot's emitter is within quick reach of its anchor.
  bool NearAnchor(const Slot& s) const;

  const Bake* bake_ = nullptr;
  bool supported_ = false;
  uint32_t vertex_count_ = 0;
  HierarchySolveQ32 solver_;
  SurfaceEmitterRefine refine_;
  EmitterBounceTable bounces_;
  std::vector<uint32_t> surface_root_;  // per surface, kBakeNoIndex if it has no tree
  VertexLeafWeights vertex_weights_;
  // first_shot_scratch_ per node; extra_ 3 per node (the first shot in every
  // channel, as the solver takes it); no_emission_ per node, all 0.
  std::vector<int64_t> coverage_scratch_, first_shot_scratch_, extra_, no_emission_;
  // A warm FE start's leaves whose emission changed (StartFrom), per node.
  std::vector<uint32_t> changed_leaves_;
  uint32_t changed_count_ = 0;
  Slot slots_[kMaxSurfaceEmitters];
  int last_sweeps_ = 0, last_warm_ = 0, last_quick_ = 0;
  bool quick_changes_ = true;
  EmitterSolveObserver* observer_ = nullptr;
};

}  // namespace relight
