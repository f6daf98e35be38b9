// Leaves to vertices (surface_emitter_vertices.h).
//
// Scaling and overflow: weights UQ0.32 summing to <= 2^32 per vertex (each
// rounded down), times values Q24 (int32), summed in int64: the sum lies in
// [-2^63, 2^63 - 2^32], which int64 holds. It is Q56, rounded to Q24. Areas at open: Q32.32 (< 2^64), summed per
// vertex in UInt128, the quotient area << 32 / sum < 2^32 + 1.
#include "surface_emitter_vertices.h"

#include "relight/base/fixed.h"
#include "relight/base/fixed_ops.h"

namespace relight {

void MakeVertexLeafWeights(const BakeHierarchy& h, uint32_t vertex_count, VertexLeafWeights* w) {
  std::vector<UInt128> area(vertex_count, 0);
  w->offsets.assign(size_t{vertex_count} + 1, 0);
  for (uint32_t k = 0; k < h.node_count(); ++k) {
    if (!h.leaf(k)) continue;
    for (int c = 0; c < h.node_corner_count[k]; ++c) {
      const uint32_t v = h.node_corners[size_t{k} * kBakeMaxNodeCorners + static_cast<size_t>(c)];
      area[v] += h.node_area[k];
      ++w->offsets[v + 1];
    }
  }
  for (uint32_t v = 0; v < vertex_count; ++v) w->offsets[v + 1] += w->offsets[v];
  w->leaf.assign(w->offsets[vertex_count], 0);
  w->weight_q32.assign(w->offsets[vertex_count], 0);
  std::vector<uint32_t> fill(w->offsets.begin(), w->offsets.end() - 1);
  for (uint32_t k = 0; k < h.node_count(); ++k) {
    if (!h.leaf(k)) continue;
    for (int c = 0; c < h.node_corner_count[k]; ++c) {
      const uint32_t v = h.node_corners[size_t{k} * kBakeMaxNodeCorners + static_cast<size_t>(c)];
      const uint32_t i = fill[v]++;
      w->leaf[i] = k;
      const UInt128 q = (static_cast<UInt128>(h.node_area[k]) << 32) / area[v];  // <= 2^32
      w->weight_q32[i] = q > UINT32_MAX ? UINT32_MAX : static_cast<uint32_t>(q);
    }
  }
}

void LeavesToVerticesQ24(const VertexLeafWeights& w, uint32_t vertex_count, const int32_t* node_q24,
                         int32_t* out) {
  for (uint32_t v = 0; v < vertex_count; ++v) {
    int64_t s0 = 0, s1 = 0, s2 = 0;
    for (uint32_t i = w.offsets[v]; i < w.offsets[v + 1]; ++i) {
      const int64_t weight = w.weight_q32[i];
      const int32_t* x = &node_q24[4 * size_t{w.leaf[i]}];
      s0 += weight * x[0];
      s1 += weight * x[1];
      s2 += weight * x[2];
    }
    out[3 * size_t{v}] = SaturateI32(RoundShiftSat64(s0, -32));
    out[3 * size_t{v} + 1] = SaturateI32(RoundShiftSat64(s1, -32));
    out[3 * size_t{v} + 2] = SaturateI32(RoundShiftSat64(s2, -32));
  }
}

}  // namespace relight
