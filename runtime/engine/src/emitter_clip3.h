// A node's polygon cut by a run-time emitter, in 3D, for adaptive refine
// (surface_emitter_refine.h): the part of the node the emitter covers, the
// emitting element whose form factors AR computes. Sutherland-Hodgman in the
// surface's plane projected along its normal's largest axis (as the FE
// coverage clip, surface_emitter_coverage.h); a crossing interpolates all
// three coordinates, so the cut corners stay on the node's plane.
// Integer-only, no allocation; thread-safe.
#pragma once

#include <cstdint>

#include "point_polygon_factor.h"
#include "relight/bake/bake.h"
#include "relight/base/fixed.h"
#include "relight/engine/surface_emitter.h"

namespace relight {

class EmitterClip3 {
 public:
  // The shape (validated by SurfaceEmitterCoverageQ32) on a surface whose
  // normal's largest axis is drop_axis.
  void Set(const SurfaceEmitterShape& shape, int drop_axis);
  // The node's polygon clipped by the emitter, corners Q16.16 metres; returns
  // their count, 0 when nothing is left.
  int Clip(const BakeHierarchy& h, const BakeMesh& mesh, uint32_t node,
           int64_t (*out)[3]) const;

 private:
  Int128 Side(int k, const int64_t* p) const;

  int a_ = 0, b_ = 1, count_ = 0;
  int64_t e_[kMaxSurfaceEmitterCorners][2] = {};  // counter-clockwise, Q16.16
};

}  // namespace relight
