// Run-time light sources on surfaces: Chandran & Srivastava's fractional
// emissivity (FE). An emitter is a convex polygon lying on one surface of the
// bake; it covers parts of that surface's quadtree (clipping, their Fig. 5
// Intersection()), the covered leaves emit, and radiosity is re-solved over
// the links the bake stores (docs/hierarchy.md). Only bakes with a hierarchy
// (sections HIER, LINK) support them.
//
// The engine drives them (Engine::SetSurfaceEmitter and friends); this header
// holds the shape they take and the fixed limits the engine sizes for.
#pragma once

#include <cstdint>
#include <string>

namespace relight {

// Slots the engine reserves at Open(); corners of one emitter polygon.
inline constexpr int kMaxSurfaceEmitters = 8;
inline constexpr int kMinSurfaceEmitterCorners = 3;
inline constexpr int kMaxSurfaceEmitterCorners = 8;
// How far a corner may lie off the surface's plane: 2 mm (Q16.16 metres).
inline constexpr int32_t kSurfaceEmitterPlaneToleranceQ16 = 131;

// How an emitter's light leaves it (docs/hierarchy.md, "AR"):
//  kFractionalEmissivity (FE): each stored node sends the emitter's covered
//    fraction of it through its links, as if spread evenly over the node;
//  kAdaptiveRefine (AR): partly covered nodes are refined to the polygon
//    itself, with new factors for their links from a fixed-point
//    point-to-polygon kernel (visibility kept from the stored link). Closer
//    to the exact light next to the emitter; the placement costs the kernel.
enum class SurfaceEmitterMethod : uint8_t { kFractionalEmissivity, kAdaptiveRefine };

// New links one adaptive-refine placement may make (EngineOptions).
inline constexpr int kDefaultSurfaceEmitterRefineLinks = 65536;
// Adaptive refine makes new factors for a link where it carries at least
// 2^-bits of the emitter's exitance (BF's F x B, B the covered fraction);
// the other links send as fractional emissivity does, with its
// source-moment term. Measured (docs/hierarchy.md, "AR"): 8 is as close to
// the naive solve as 10 at 0.2-0.4x the new links.
inline constexpr int kDefaultSurfaceEmitterRefineBits = 8;
// Memory for the later bounces of new emitters, tabulated at Open
// (EngineOptions::emitter_bounce_table_bytes).
inline constexpr int64_t kDefaultEmitterBounceTableBytes = int64_t{32} << 20;

struct SurfaceEmitterShape {
  std::string surface;  // the bake's surface name (BakeMesh::surface_names)
  int corner_count = 0;  // kMinSurfaceEmitterCorners .. kMaxSurfaceEmitterCorners
  // Q16.16 metres, xyz per corner, in order around a convex polygon (either
  // way round: it emits from the surface's lit side).
  int32_t corners_q16[kMaxSurfaceEmitterCorners][3] = {};
  SurfaceEmitterMethod method = SurfaceEmitterMethod::kAdaptiveRefine;
};

}  // namespace relight
