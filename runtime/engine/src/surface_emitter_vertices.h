// Leaf values to vertex values the way the baker forms its vertex basis
// (baker_core AverageToVertices): each vertex takes the area-weighted mean of
// the leaves (patches) it is a corner of. Integer-only; thread-safe.
#pragma once

#include <cstdint>

#include "relight/bake/bake.h"
#include "relight/base/fixed.h"

namespace relight {

// Sum of the areas (Q32.32 m^2) of the leaves around each vertex; 0 for a
// vertex of no leaf. vertex_area has mesh.vertex_count() entries.
void VertexLeafAreas(const BakeHierarchy& h, uint32_t vertex_count, UInt128* vertex_area);

// out[3 v + c] = mean over v's leaves k of node_q32[3 k + c] (Q32), as Q24
// (saturated to int32), every channel c. sum is caller scratch of
// 3 x vertex_count entries.
void LeavesToVerticesQ24(const BakeHierarchy& h, const UInt128* vertex_area, uint32_t vertex_count,
                         const int64_t* node_q32, Int128* sum, int32_t* out);

}  // namespace relight
