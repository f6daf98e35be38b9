// Chunked draws: see scene_chunks.h.
#define GL_GLEXT_PROTOTYPES 1
#include "scene_chunks.h"

#include <GL/gl.h>

#include <algorithm>
#include <cstddef>

namespace relight::render {

void DrawTriangleArrays(uint32_t triangles, uint32_t per_scene) {
  for (uint32_t first = 0; first < triangles; first += per_scene) {
    if (first > 0) glFlush();
    const uint32_t n = std::min(per_scene, triangles - first);
    glDrawArrays(GL_TRIANGLES, static_cast<GLint>(first * 3), static_cast<GLsizei>(n * 3));
  }
}
void DrawTriangleElements(uint32_t triangles, uint32_t per_scene) {
  for (uint32_t first = 0; first < triangles; first += per_scene) {
    if (first > 0) glFlush();
    const uint32_t n = std::min(per_scene, triangles - first);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(n * 3), GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(size_t{first} * 3 * sizeof(GLuint)));
  }
}

}  // namespace relight::render
