// Fractional emissivity (Chandran & Srivastava, Fig. 5 Intersection()): how
// much of each leaf of a surface's quadtree a convex emitter polygon covers.
// Integer Sutherland-Hodgman in the surface's plane, projected along the
// normal's largest axis: areas all scale by the same factor there, so the
// covered fraction of each leaf is exact up to the Q.40 rounding of the
// clipped corners. Integer-only, no allocation; thread-safe.
#pragma once

#include <cstdint>

#include "relight/bake/bake.h"
#include "relight/base/status.h"

namespace relight {

// Fraction of a leaf the emitter covers, 2^32 = all of it.
inline constexpr int kCoverageFracBits = 32;

// Clips the polygon (corner_count corners, Q16.16 metres) against the tree
// whose root node is `root`, from the root down: a node inside the polygon
// covers all of its leaves, a node outside none, a partly covered leaf its
// clipped fraction. Writes leaf_fraction_q32[k] for the leaves it touches
// (array of node_count, zeroed by the caller; other entries left alone).
// Returns kInvalidArgument, saying why, for a corner off the surface's plane
// by more than kSurfaceEmitterPlaneToleranceQ16, a polygon that is not
// strictly convex (or has fewer than 3 / more than 8 corners), or one that
// does not overlap the surface; leaf_fraction_q32 is then untouched.
Status SurfaceEmitterCoverageQ32(const BakeHierarchy& hierarchy, const BakeMesh& mesh,
                                 uint32_t root, const int32_t (*corners_q16)[3], int corner_count,
                                 int64_t* leaf_fraction_q32);

}  // namespace relight
