// OsMesaFrame's state (osmesa_frame.h), shared by the files that work on it:
// osmesa_frame.cc (the context, the mesh and the public calls) and
// osmesa_frame_passes.cc (the ID pass, the culling's list, the resolve's
// table and the resolved frame). Private to the render library.
#pragma once

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/osmesa.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "camera.h"
#include "relight/base/status.h"
#include "relight/base/worker_pool.h"
#include "relight/render/osmesa_frame.h"

namespace relight {
namespace render {

inline constexpr uint8_t kBackgroundLevel = 32;  // dark grey, in every channel

// OK, or kInternal naming `where` and the first GL error (the others are cleared).
Status CheckGl(const char* where);

inline GLsizeiptr Bytes(size_t count, size_t elem_size) { return static_cast<GLsizeiptr>(count * elem_size); }

}  // namespace render

struct OsMesaFrame::Impl {
  OSMesaContext ctx = nullptr;
  int width = 0;
  int height = 0;
  std::vector<GLubyte> color_rgba;  // OSMesa's colour buffer, bottom row first

  uint32_t vertex_count = 0;
  uint32_t triangle_count = 0;
  render::SceneSphere scene;
  // Buffer objects: shared-vertex mesh for the colour pass, un-shared
  // vertices (3 per triangle, flat ID colour) for the ID pass.
  GLuint position_vbo = 0;
  GLuint color_vbo = 0;
  GLuint index_vbo = 0;
  GLuint id_position_vbo = 0;
  GLuint id_color_vbo = 0;

  // Hidden-triangle culling (visible_triangles.h): at the second Draw with
  // an unchanged camera an ID pass finds the triangles the camera shows, and
  // later draws send only those (same pixels, about a third of the stage's
  // triangles). A camera that moves every frame never pays for the ID pass.
  // All arrays are sized at Init: nothing is allocated per frame.
  GLuint visible_index_vbo = 0;
  std::vector<uint32_t> triangles;        // the full index list, 3 per triangle
  std::vector<uint32_t> visible_indices;  // room for all of them
  std::vector<uint8_t> triangle_seen;     // scratch, one per triangle
  uint32_t visible_count = 0;
  bool visible_valid = false;  // visible_index_vbo holds the list for the current camera
  bool cull_hidden = true;
  int draws_at_camera = 0;
  uint32_t last_drawn_triangles = 0;

  // The still camera's resolve (pixel_resolve.h): the same ID pass, turned
  // in place into a table of slot and weights per pixel, after which frames
  // at that camera skip llvmpipe. color_rgba holds the table while
  // table_valid; any GL draw into it ends that.
  std::vector<float> positions_m;        // what llvmpipe draws, 3 per vertex
  std::vector<uint16_t> slot_of_triangle;
  std::vector<uint64_t> slot_colours;    // per frame: 3 spread colours per shown triangle
  bool resolve = true;
  bool table_valid = false;
  bool table_refused = false;  // this camera shows more triangles than a table names
  bool last_resolved = false;
  std::unique_ptr<WorkerPool> resolve_pool;  // SetResolveThreads > 1: the rows split over it

  CameraView view;
  render::CameraFrame camera;
  render::CameraFrame drawn_camera;  // the camera of the last draw (for unprojection)
  bool has_drawn = false;

  ~Impl() { Release(); }

  // Forgets the mesh and what was drawn of it; the context stays.
  void ForgetMesh() {
    visible_valid = false;
    draws_at_camera = 0;
    last_drawn_triangles = 0;
    has_drawn = false;
    table_valid = false;
    table_refused = false;
    last_resolved = false;
  }

  void Release() {
    if (ctx != nullptr) {
      // Buffer objects die with the context; only one context lives at a time.
      OSMesaDestroyContext(ctx);
      ctx = nullptr;
    }
    position_vbo = color_vbo = index_vbo = id_position_vbo = id_color_vbo = visible_index_vbo = 0;
    ForgetMesh();
    width = height = 0;
  }

  // A new mesh in the same context: its shaders, already compiled, stay.
  Status DeleteMeshBuffers() {
    const GLuint ids[6] = {position_vbo, color_vbo, index_vbo, id_position_vbo, id_color_vbo, visible_index_vbo};
    glDeleteBuffers(6, ids);
    position_vbo = color_vbo = index_vbo = id_position_vbo = id_color_vbo = visible_index_vbo = 0;
    ForgetMesh();
    return render::CheckGl("freeing the previous mesh");
  }

  Status MakeCurrent() {
    if (ctx == nullptr) return Status(StatusCode::kInvalidArgument, "render: frame not initialised");
    if (OSMesaGetCurrentContext() == ctx) return Status::Ok();
    if (!OSMesaMakeCurrent(ctx, color_rgba.data(), GL_UNSIGNED_BYTE, width, height)) {
      return Status(StatusCode::kInternal, "render: OSMesaMakeCurrent failed");
    }
    return Status::Ok();
  }

  void UpdateCamera() {
    camera = render::MakeCameraFrame(view, static_cast<double>(width) / height, scene);
  }

  void LoadMatrices() {
    float m[16];
    render::ProjectionMatrix(camera, m);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixf(m);
    render::ViewMatrix(camera, m);
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixf(m);
  }

  Status Upload(const BakeMesh& mesh);
  Status Finish(const char* pass);
  Status DrawIdPass();
  Status FindVisibleTriangles();
  void BuildTable();
  void Resolve(const uint8_t* vertex_rgb8, uint8_t* out_rgb8);
};

}  // namespace relight
