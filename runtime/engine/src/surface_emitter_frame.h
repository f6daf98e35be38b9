// A surface's plane in integers, for run-time emitters: its normal, the
// link gradients' (u, v) frame and node centroids in that frame, all from the
// Q16.16 mesh positions of node corners. Integer-only, thread-safe.
#pragma once

#include <cstdint>

#include "relight/bake/bake.h"
#include "relight/base/fixed.h"

namespace relight {

// Newell's normal of a node's polygon: twice its vector area, Q32 m^2,
// pointing to the lit side (corners are counter-clockwise from there).
void NodeNormalQ32(const BakeHierarchy& h, const BakeMesh& mesh, uint32_t node, Int128 normal[3]);

// The frame docs/bake-format.md gives the link gradients: origin at the
// root's corner 0, u along its first edge, v = n x u. Unit vectors Q1.30.
struct SurfaceFrameQ30 {
  int32_t origin_q16[3];
  int32_t u_q30[3], v_q30[3];
  int drop_axis;  // the normal's largest component: projecting it away keeps area ratios
};
void MakeSurfaceFrameQ30(const BakeHierarchy& h, const BakeMesh& mesh, uint32_t root,
                         SurfaceFrameQ30* frame);

// A node's area centroid in the frame, (u, v) Q16.16 metres.
void NodeCentreUvQ16(const BakeHierarchy& h, const BakeMesh& mesh, const SurfaceFrameQ30& frame,
                     uint32_t node, int32_t uv_q16[2]);

}  // namespace relight
