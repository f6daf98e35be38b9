// The engine's run-time emitter slots (relight/surface_emitter.h): per slot
// the emitter's coverage of its surface (placed once per geometry), its
// solved light per unit luminance at every vertex, per channel, and its
// luminance. A luminance change only rescales the solved light (the solve is
// linear), so it costs one multiply-add per vertex and channel.
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

  // Solves every placed slot whose geometry changed; returns how many.
  int SolvePending();
  // Adds every placed emitter's light to LightQ12 vertex luminance (3 per vertex).
  void AddTo(int32_t* vertex_q12) const;

  int last_sweeps() const { return last_sweeps_; }
  // Null or an observer that outlives this; called from SolvePending().
  void set_observer(EmitterSolveObserver* observer) { observer_ = observer; }
  // The slot's luminance (3 x LightQ12) if it is placed and solved, else null.
  const int32_t* solved_luminance_q12(int slot) const {
    const Slot& s = slots_[slot];
    return s.placed && !s.dirty ? s.luminance_q12 : nullptr;
  }

 private:
  struct Slot {
    bool placed = false, dirty = false;
    int32_t luminance_q12[3] = {0, 0, 0};
    std::vector<int64_t> coverage_q32;  // per node, covered fraction of each leaf
    std::vector<int32_t> unit_q24;      // 3 per vertex
  };
  Status CheckSlot(int slot) const;

  const Bake* bake_ = nullptr;
  bool supported_ = false;
  uint32_t vertex_count_ = 0;
  HierarchySolveQ32 solver_;
  std::vector<uint32_t> surface_root_;  // per surface, kBakeNoIndex if it has no tree
  std::vector<UInt128> vertex_area_;
  std::vector<Int128> vertex_sum_;
  std::vector<int64_t> coverage_scratch_, exitance_;
  Slot slots_[kMaxSurfaceEmitters];
  int last_sweeps_ = 0;
  EmitterSolveObserver* observer_ = nullptr;
};

}  // namespace relight
