#include "visible_triangles.h"

#include <cstring>

namespace relight::render {

uint32_t CompactVisibleTriangles(const uint8_t* id_rgba, size_t pixels, const uint32_t* triangles,
                                 uint32_t triangle_count, uint8_t* seen, uint32_t* out_indices) {
  std::memset(seen, 0, triangle_count);
  for (size_t p = 0; p < pixels; ++p) {
    const uint32_t code = TriangleCode(id_rgba + 4 * p);
    if (code != 0 && code <= triangle_count) seen[code - 1] = 1;
  }
  uint32_t shown = 0;
  for (uint32_t t = 0; t < triangle_count; ++t) {
    if (seen[t] == 0) continue;
    std::memcpy(out_indices + size_t{3} * shown, triangles + size_t{3} * t, 3 * sizeof(uint32_t));
    ++shown;
  }
  return shown;
}

}  // namespace relight::render
