// OsMesaFrame's per-camera passes (see osmesa_frame_impl.h): the ID pass,
// the culling's list of shown triangles, the resolve's table built from the
// same pass, and a frame resolved from that table.
#include <cstddef>

#include "osmesa_frame_impl.h"
#include "pixel_resolve.h"
#include "scene_chunks.h"
#include "visible_triangles.h"

namespace relight {
namespace render {
namespace {

const char* GlErrorName(GLenum e) {
  switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    default: return "GL error";
  }
}

}  // namespace

Status CheckGl(const char* where) {
  const GLenum e = glGetError();
  if (e == GL_NO_ERROR) return Status::Ok();
  while (glGetError() != GL_NO_ERROR) {
  }
  return Status(StatusCode::kInternal, StrFormat("render: %s: %s (0x%x)", where, GlErrorName(e), e));
}

}  // namespace render

using render::Bytes;
using render::CheckGl;

// Waits for llvmpipe, which also copies the frame into color_rgba.
Status OsMesaFrame::Impl::Finish(const char* pass) {
  glFinish();
  RELIGHT_RETURN_IF_ERROR(CheckGl(pass));
  drawn_camera = camera;
  has_drawn = true;
  return Status::Ok();
}

// Draws every triangle in its ID colour (flat: exact codes); color_rgba then
// holds the codes, bottom row first.
Status OsMesaFrame::Impl::DrawIdPass() {
  table_valid = false;  // the pass draws over the table
  LoadMatrices();
  glShadeModel(GL_FLAT);
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (triangle_count > 0) {
    glBindBuffer(GL_ARRAY_BUFFER, id_color_vbo);
    glColorPointer(3, GL_UNSIGNED_BYTE, 0, nullptr);
    glBindBuffer(GL_ARRAY_BUFFER, id_position_vbo);
    glVertexPointer(3, GL_FLOAT, 0, nullptr);
    render::DrawTriangleArrays(triangle_count, render::kTrianglesPerScene);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
  }
  glShadeModel(GL_SMOOTH);
  return Finish("the ID pass");
}

// From the ID pass in color_rgba: the shown triangles into visible_index_vbo.
Status OsMesaFrame::Impl::FindVisibleTriangles() {
  visible_count = render::CompactVisibleTriangles(color_rgba.data(), static_cast<size_t>(width) * height,
                                                  triangles.data(), triangle_count, triangle_seen.data(),
                                                  visible_indices.data());
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, visible_index_vbo);
  glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, Bytes(size_t{visible_count} * 3, sizeof(GLuint)),
                  visible_indices.data());
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
  RELIGHT_RETURN_IF_ERROR(CheckGl("uploading the visible triangles"));
  visible_valid = true;
  return Status::Ok();
}

// From the ID pass in color_rgba, right after FindVisibleTriangles: the
// resolve's table, in place.
void OsMesaFrame::Impl::BuildTable() {
  table_valid = false;
  if (!resolve || visible_count > render::kResolveMaxSlots) {
    table_refused = resolve;
    return;
  }
  render::NumberShownTriangles(triangle_seen.data(), triangle_count, slot_of_triangle.data());
  render::BuildPixelTable(camera, width, height, positions_m.data(), triangles.data(), slot_of_triangle.data(),
                          triangle_count, color_rgba.data());
  table_valid = true;
}

// From the table and this frame's slot colours, the frame's rows split
// evenly over the pool (the same bytes however they are split).
void OsMesaFrame::Impl::Resolve(const uint8_t* vertex_rgb8, uint8_t* out_rgb8) {
  render::GatherSlotColours(visible_indices.data(), visible_count, vertex_rgb8, slot_colours.data());
  if (resolve_pool == nullptr) {
    render::ResolvePixels(color_rgba.data(), width, height, slot_colours.data(), render::kBackgroundLevel, out_rgb8);
    return;
  }
  struct ResolveJob {
    const Impl* frame;
    uint8_t* out;
    int threads;
  };
  ResolveJob job{this, out_rgb8, resolve_pool->threads()};
  resolve_pool->Run(
      [](void* context, int thread) {
        const ResolveJob& j = *static_cast<const ResolveJob*>(context);
        const int h = j.frame->height;
        render::ResolveRowsWith(render::ResolveBody::kBest, j.frame->color_rgba.data(), j.frame->width, h,
                                h * thread / j.threads, h * (thread + 1) / j.threads, j.frame->slot_colours.data(),
                                render::kBackgroundLevel, j.out);
      },
      &job);
}

}  // namespace relight
