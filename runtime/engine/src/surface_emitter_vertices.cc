// Leaves to vertices (surface_emitter_vertices.h).
//
// Scaling and overflow: leaf areas Q32.32 (< 2^64) x values Q32 (< 2^40)
// summed over a vertex's few leaves in Int128 (< 2^108); divided by the
// area sum gives Q32, shifted to Q24 and saturated.
#include "surface_emitter_vertices.h"

#include "relight/base/fixed_ops.h"

namespace relight {

void VertexLeafAreas(const BakeHierarchy& h, uint32_t vertex_count, UInt128* vertex_area) {
  for (uint32_t v = 0; v < vertex_count; ++v) vertex_area[v] = 0;
  for (uint32_t k = 0; k < h.node_count(); ++k) {
    if (!h.leaf(k)) continue;
    for (int c = 0; c < h.node_corner_count[k]; ++c)
      vertex_area[h.node_corners[size_t{k} * kBakeMaxNodeCorners + static_cast<size_t>(c)]] +=
          h.node_area[k];
  }
}

void LeavesToVerticesQ24(const BakeHierarchy& h, const UInt128* vertex_area, uint32_t vertex_count,
                         const int64_t* node_q32, Int128* sum, int32_t* out) {
  for (size_t i = 0; i < size_t{vertex_count} * 3; ++i) sum[i] = 0;
  for (uint32_t k = 0; k < h.node_count(); ++k) {
    if (!h.leaf(k)) continue;
    Int128 weighted[3];
    for (int c = 0; c < 3; ++c) weighted[c] = static_cast<Int128>(h.node_area[k]) * node_q32[3 * size_t{k} + c];
    for (int j = 0; j < h.node_corner_count[k]; ++j) {
      const size_t v = h.node_corners[size_t{k} * kBakeMaxNodeCorners + static_cast<size_t>(j)];
      for (int c = 0; c < 3; ++c) sum[3 * v + c] += weighted[c];
    }
  }
  for (size_t i = 0; i < size_t{vertex_count} * 3; ++i) {
    int32_t value = 0;
    if (vertex_area[i / 3] != 0) {
      const Int128 area = static_cast<Int128>(vertex_area[i / 3]);
      const Int128 half = sum[i] >= 0 ? area / 2 : -(area / 2);
      value = SaturateI32(RoundShiftSat64((sum[i] + half) / area, -8));
    }
    out[i] = value;
  }
}

}  // namespace relight
