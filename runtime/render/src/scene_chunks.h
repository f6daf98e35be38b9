// Draws of many triangles in several llvmpipe scenes (osmesa_frame.cc).
#pragma once

#include <cstdint>

namespace relight::render {

// llvmpipe bins a whole scene (every triangle drawn since the last flush)
// before it rasterises, and frees the bins' blocks after: the stage's 32 270
// triangles held 3.7 MB of bins at once, the peak of relightd's start-up. The
// draws of every triangle (a first frame, the ID pass of a new camera) send
// at most this many a scene; a flush between them keeps the order, so the
// pixels are the same. The culled draws of the frames that follow (a third of
// the triangles) stay whole: a flush costs a pass over every tile (measured:
// 4096 a scene for them too added 0.8 ms to the draw's median).
constexpr uint32_t kTrianglesPerScene = 2048;

// glDrawArrays, or glDrawElements from the bound element buffer (unsigned
// int indices), of `triangles` triangles, `per_scene` at a time (> 0), with
// the current context and arrays.
void DrawTriangleArrays(uint32_t triangles, uint32_t per_scene);
void DrawTriangleElements(uint32_t triangles, uint32_t per_scene);

}  // namespace relight::render
