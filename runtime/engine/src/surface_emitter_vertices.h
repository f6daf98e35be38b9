// Leaf values to vertex values the way the baker forms its vertex basis
// (baker_core AverageToVertices): each vertex takes the area-weighted mean of
// the leaves (patches) it is a corner of. The weights (leaf area over the
// vertex's leaves' area) are computed once at open, so the per-solve pass is
// a few multiply-adds per vertex and no division. Thread-safe.
#pragma once

#include <cstdint>
#include <vector>

#include "relight/bake/bake.h"

namespace relight {

// Vertex v averages leaves leaf[i] with weight_q32[i] (UQ0.32, rounded down
// so a vertex's weights sum to at most 1), i in [offsets[v], offsets[v + 1]).
struct VertexLeafWeights {
  std::vector<uint32_t> offsets, leaf, weight_q32;
};

// Open time (allocates). A vertex of no leaf gets no entries (value 0).
void MakeVertexLeafWeights(const BakeHierarchy& h, uint32_t vertex_count, VertexLeafWeights* w);

// out[3 v + c] = sum of weight x node_q24[4 leaf + c] (Q24 in, 4 per node as
// the solver keeps them; Q24 out).
// Integer-only, allocation-free.
void LeavesToVerticesQ24(const VertexLeafWeights& w, uint32_t vertex_count, const int32_t* node_q24,
                         int32_t* out);

}  // namespace relight
