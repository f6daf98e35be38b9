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
#include "surface_emitter_solve.h"
#include "surface_emitter_vertices.h"
#include "worker_pool.h"

namespace relight {

class SurfaceEmitters {
 public:
  // A bake without a hierarchy opens fine; every call then returns kUnsupported.
  Status Open(const Bake& bake);

  // Clips the shape against its surface and stores the coverage; the solve
  // runs at the next SolvePending(). kUnsupported (no hierarchy), kNotFound
  // (no surface of that name), kInvalidArgument (slot, or the shape: off the
  // plane, not convex, not on the surface). On error nothing changes.
  Status Place(int slot, const SurfaceEmitterShape& shape);
  // LightQ12 cd/m^2 per channel, >= 0. kInvalidArgument for a bad slot or value.
  Status SetLuminance(int slot, const LightQ12 rgb[3]);
  Status Remove(int slot);

  // Solves every placed slot whose geometry changed, the sweeps on `pool`
  // (may be null: this thread); returns how many.
  int SolvePending(WorkerPool* pool);
  // Adds every placed emitter's light to LightQ12 vertex luminance (3 per vertex).
  void AddTo(int32_t* vertex_q12) const;

  int last_sweeps() const { return last_sweeps_; }
  // Solves of the last SolvePending that started from the previous solution.
  int last_warm_starts() const { return last_warm_; }

 private:
  struct Solution {
    bool solved = false;                // exitance and unit_q24 are for coverage_q32
    std::vector<int64_t> coverage_q32;  // per node, covered fraction of each leaf
    std::vector<int64_t> exitance_q32;  // 3 per node, per unit luminance
    std::vector<int32_t> unit_q24;      // 3 per vertex
  };
  struct Slot {
    bool placed = false;
    bool moved = false;  // the last Place found it placed: a move, not a new light
    int32_t luminance_q12[3] = {0, 0, 0};
    Solution now, before;  // before: the last solved placement the slot moved from
  };
  Status CheckSlot(int slot) const;
  void StartFrom(const Slot& s, int64_t* exitance_q32, bool* warm) const;

  const Bake* bake_ = nullptr;
  bool supported_ = false;
  uint32_t vertex_count_ = 0;
  HierarchySolveQ32 solver_;
  std::vector<uint32_t> surface_root_;  // per surface, kBakeNoIndex if it has no tree
  VertexLeafWeights vertex_weights_;
  std::vector<int64_t> coverage_scratch_;
  Slot slots_[kMaxSurfaceEmitters];
  int last_sweeps_ = 0, last_warm_ = 0;
};

}  // namespace relight
