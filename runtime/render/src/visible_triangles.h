// Which triangles an ID pass shows, as a shorter index list for the colour
// pass. A triangle that wins no pixel at a camera can be left out of that
// camera's colour pass without changing a single pixel: with GL_LESS the
// pixel keeps the first fragment, in draw order, of least depth, and a
// triangle that is that fragment nowhere is never it after others go. The ID
// pass rasterises the same positions in the same order, so it names exactly
// the winners. On the stage (32 270 triangles) the default camera sees 10 463.
#pragma once

#include <cstddef>
#include <cstdint>

namespace relight::render {

// id_rgba: an ID pass's RGBA pixels, triangle t drawn as the 24-bit code
// t + 1 in R, G, B (0: background); codes above triangle_count are ignored.
// triangles: 3 vertex indices per triangle. seen: triangle_count bytes of
// scratch. Writes the shown triangles' indices, in their draw order, to
// out_indices (room for 3 x triangle_count) and returns how many triangles.
uint32_t CompactVisibleTriangles(const uint8_t* id_rgba, size_t pixels, const uint32_t* triangles,
                                 uint32_t triangle_count, uint8_t* seen, uint32_t* out_indices);

// The ID pass's code of one RGBA pixel: 0 for background, else triangle + 1.
inline uint32_t TriangleCode(const uint8_t* rgba) {
  return static_cast<uint32_t>(rgba[0]) | static_cast<uint32_t>(rgba[1]) << 8 |
         static_cast<uint32_t>(rgba[2]) << 16;
}

}  // namespace relight::render
