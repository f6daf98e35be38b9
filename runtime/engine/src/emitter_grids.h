// Run-time surface emitters on the calculation grids (issue 15 item 4): after
// an emitter's solve, each grid point gathers sum f x B over the bake's
// node-to-point links (section GLNK, BakeHierarchy::grid_link_*), giving per
// slot the point's illuminance per cd/m^2 of the emitter, per channel; the
// mix scales it by the slot's luminance, like the vertices. The light
// straight from the emitter and its interreflections both arrive through
// the nodes' exitance, and both go into grid_illuminance(), not the direct
// grids (those are the luminaires' exact direct term).
//
// Open() allocates; Solved() and AddTo() are integer-only and allocate
// nothing. Not thread-safe.
#pragma once

#include <cstdint>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/engine/surface_emitter.h"
#include "surface_emitters.h"

namespace relight {

class EmitterGrids : public EmitterSolveObserver {
 public:
  // A bake without grids or grid links opens fine and adds nothing.
  void Open(const Bake& bake);
  bool active() const { return active_; }

  // exitance_q32: 3 per node, the slot's solve for unit emission (coverage 1 = 1 lm/m^2).
  void OnSolved(int slot, const int64_t* exitance_q32) override;
  // Adds every solved slot's light at its luminance to the grids (3 per point each).
  void AddTo(const SurfaceEmitters& emitters, std::vector<std::vector<int32_t>>* grid_q12) const;

  // Lux per cd/m^2 of the emitter in `slot`, Q24, 3 per point over all grids.
  const int32_t* unit_q24(int slot) const { return slots_[slot].data(); }

 private:
  const BakeHierarchy* h_ = nullptr;
  bool active_ = false;
  std::vector<uint32_t> grid_first_;  // per grid, its first point in the link numbering
  std::vector<int32_t> slots_[kMaxSurfaceEmitters];
};

}  // namespace relight
