// OSMesa (Mesa llvmpipe) renderer. The legacy fixed-function pipeline is all
// we need: vertex colours are already tone-mapped sRGB, so lighting is off and
// GL does no gamma work; GL_SMOOTH gives Gouraud shading. With the
// still-camera resolve (the default) a camera's first Draw runs the ID pass,
// and that frame and every later one at the camera come from the pass's
// table instead of a colour pass (pixel_resolve.h): llvmpipe draws again only
// when the camera moves.
//
// llvmpipe rasterises on LP_NUM_THREADS threads (default: one per CPU). We
// leave the environment alone; set it outside the process to share cores.
#include "relight/render/osmesa_frame.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <utility>

#include "camera.h"
#include "osmesa_frame_impl.h"
#include "pixel_resolve.h"
#include "rgba_rows.h"
#include "scene_chunks.h"
#include "visible_triangles.h"

namespace relight {
namespace {

constexpr int kMaxSide = 16384;  // llvmpipe's largest framebuffer side
// The ID pass stores triangle index + 1 in 24 bits of RGB; 0 is background.
constexpr uint32_t kMaxTriangles = 0xFFFFFEu;
constexpr uint32_t kNoTriangle = 0xFFFFFFFFu;
constexpr float kBackgroundGrey = render::kBackgroundLevel / 255.0f;

}  // namespace

using render::Bytes;
using render::CheckGl;

Status OsMesaFrame::Impl::Upload(const BakeMesh& mesh) {
  // Q16.16 metres to float, once.
  std::vector<GLfloat> pos(mesh.positions.size());
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (size_t i = 0; i < mesh.positions.size(); ++i) {
    const double v = mesh.positions[i] / 65536.0;
    pos[i] = static_cast<GLfloat>(v);
    const size_t axis = i % 3;
    if (i < 3 || v < lo[axis]) lo[axis] = v;
    if (i < 3 || v > hi[axis]) hi[axis] = v;
  }
  double r2 = 0;
  for (int a = 0; a < 3; ++a) {
    scene.centre_m[a] = 0.5 * (lo[a] + hi[a]);
    r2 += 0.25 * (hi[a] - lo[a]) * (hi[a] - lo[a]);
  }
  scene.radius_m = std::sqrt(r2);

  std::vector<GLfloat> id_pos(static_cast<size_t>(triangle_count) * 9);
  std::vector<GLubyte> id_rgb(static_cast<size_t>(triangle_count) * 9);
  for (uint32_t t = 0; t < triangle_count; ++t) {
    const uint32_t code = t + 1;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.triangles[static_cast<size_t>(t) * 3 + k];
      const size_t o = (static_cast<size_t>(t) * 3 + k) * 3;
      for (int a = 0; a < 3; ++a) id_pos[o + a] = pos[static_cast<size_t>(v) * 3 + a];
      id_rgb[o + 0] = static_cast<GLubyte>(code & 0xFF);
      id_rgb[o + 1] = static_cast<GLubyte>((code >> 8) & 0xFF);
      id_rgb[o + 2] = static_cast<GLubyte>((code >> 16) & 0xFF);
    }
  }

  GLuint ids[6];
  glGenBuffers(6, ids);
  position_vbo = ids[0];
  color_vbo = ids[1];
  index_vbo = ids[2];
  id_position_vbo = ids[3];
  id_color_vbo = ids[4];
  visible_index_vbo = ids[5];
  glBindBuffer(GL_ARRAY_BUFFER, position_vbo);
  glBufferData(GL_ARRAY_BUFFER, Bytes(pos.size(), sizeof(GLfloat)), pos.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, color_vbo);
  glBufferData(GL_ARRAY_BUFFER, Bytes(vertex_count, 3), nullptr, GL_STREAM_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, id_position_vbo);
  glBufferData(GL_ARRAY_BUFFER, Bytes(id_pos.size(), sizeof(GLfloat)), id_pos.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, id_color_vbo);
  glBufferData(GL_ARRAY_BUFFER, Bytes(id_rgb.size(), 1), id_rgb.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_vbo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, Bytes(mesh.triangles.size(), sizeof(GLuint)),
               mesh.triangles.data(), GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, visible_index_vbo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, Bytes(mesh.triangles.size(), sizeof(GLuint)), nullptr, GL_DYNAMIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
  triangles = mesh.triangles;
  visible_indices.assign(mesh.triangles.size(), 0);
  triangle_seen.assign(triangle_count, 0);
  slot_of_triangle.assign(triangle_count, 0);
  slot_colours.assign(size_t{3} * std::min(triangle_count, render::kResolveMaxSlots), 0);
  positions_m = std::move(pos);
  return CheckGl("uploading the mesh");
}
OsMesaFrame::OsMesaFrame() : impl_(new Impl) {}
OsMesaFrame::~OsMesaFrame() = default;

int OsMesaFrame::width() const { return impl_->width; }
int OsMesaFrame::height() const { return impl_->height; }

Status OsMesaFrame::Init(int width, int height, const BakeMesh& mesh) {
  Impl& m = *impl_;
  if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide) {
    return Status(StatusCode::kInvalidArgument,
                  StrFormat("render: frame size %dx%d outside 1..%d", width, height, kMaxSide));
  }
  if (mesh.positions.size() % 3 != 0 || mesh.triangles.size() % 3 != 0) {
    return Status(StatusCode::kInvalidArgument, "render: mesh arrays are not whole xyz / triangles");
  }
  if (mesh.triangle_count() > kMaxTriangles) {
    return Status(StatusCode::kInvalidArgument,
                  StrFormat("render: %u triangles exceed the ID pass limit %u", mesh.triangle_count(),
                            kMaxTriangles));
  }
  const uint32_t vertex_count = mesh.vertex_count();
  for (size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (mesh.triangles[i] >= vertex_count) {
      return Status(StatusCode::kInvalidArgument,
                    StrFormat("render: triangle %zu uses vertex %u of %u", i / 3, mesh.triangles[i],
                              vertex_count));
    }
  }

  if (m.ctx != nullptr && width == m.width && height == m.height) {
    // The same frame size: keep the context, so llvmpipe compiles no shader
    // again (a bake reload; the mesh of FramePipeline::WarmUp replaced).
    m.vertex_count = vertex_count;
    m.triangle_count = mesh.triangle_count();
    Status st = m.MakeCurrent();
    if (st.ok()) st = m.DeleteMeshBuffers();
    if (st.ok()) st = m.Upload(mesh);
    if (!st.ok()) {
      m.Release();
      return st;
    }
    m.UpdateCamera();
    return Status::Ok();
  }
  // A new context only after the old one is gone (PITFALLS: OSMesa).
  m.Release();
  m.vertex_count = vertex_count;
  m.triangle_count = mesh.triangle_count();
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         24,
                         OSMESA_STENCIL_BITS,
                         0,
                         OSMESA_ACCUM_BITS,
                         0,
                         OSMESA_PROFILE,
                         OSMESA_COMPAT_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         2,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         1,
                         0};
  m.ctx = OSMesaCreateContextAttribs(attribs, nullptr);
  if (m.ctx == nullptr) return Status(StatusCode::kInternal, "render: OSMesa refused a GL 2.1 context");
  m.width = width;
  m.height = height;
  m.color_rgba.assign(static_cast<size_t>(width) * height * 4, 0);
  if (!OSMesaMakeCurrent(m.ctx, m.color_rgba.data(), GL_UNSIGNED_BYTE, width, height)) {
    m.Release();
    return Status(StatusCode::kInternal, "render: OSMesaMakeCurrent failed");
  }

  glViewport(0, 0, width, height);
  glDisable(GL_LIGHTING);
  glDisable(GL_CULL_FACE);  // rooms are seen from inside; keep both faces
  glDisable(GL_DITHER);     // exact colours, and exact IDs in the ID pass
  glDisable(GL_MULTISAMPLE);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glEnableClientState(GL_VERTEX_ARRAY);
  glEnableClientState(GL_COLOR_ARRAY);

  Status st = m.Upload(mesh);
  if (!st.ok()) {
    m.Release();
    return st;
  }
  m.UpdateCamera();
  return Status::Ok();
}

void OsMesaFrame::SetCamera(const CameraView& camera) {
  Impl& m = *impl_;
  const bool same = std::memcmp(&m.view, &camera, sizeof(CameraView)) == 0;
  m.view = camera;
  if (m.ctx != nullptr) m.UpdateCamera();
  if (!same) {
    m.visible_valid = false;
    m.draws_at_camera = 0;
    m.table_valid = false;
    m.table_refused = false;
  }
}

void OsMesaFrame::SetHiddenTriangleCulling(bool on) { impl_->cull_hidden = on; }

void OsMesaFrame::SetStillCameraResolve(bool on) {
  impl_->resolve = on;
  if (!on) impl_->table_refused = false;
}

bool OsMesaFrame::last_draw_resolved() const { return impl_->last_resolved; }

void OsMesaFrame::SetResolveThreads(int threads) {
  Impl& m = *impl_;
  threads = std::clamp(threads, 1, kMaxEngineThreads);
  const int now = m.resolve_pool != nullptr ? m.resolve_pool->threads() : 1;
  if (threads == now) return;
  m.resolve_pool.reset();
  if (threads == 1) return;
  m.resolve_pool = std::make_unique<WorkerPool>();
  m.resolve_pool->Start(threads);
}

uint32_t OsMesaFrame::last_drawn_triangles() const { return impl_->last_drawn_triangles; }

Status OsMesaFrame::Draw(const uint8_t* vertex_rgb8, uint8_t* out_rgb8) {
  Impl& m = *impl_;
  if (out_rgb8 == nullptr || (vertex_rgb8 == nullptr && m.vertex_count > 0)) {
    return Status(StatusCode::kInvalidArgument, "render: Draw: null buffer");
  }
  RELIGHT_RETURN_IF_ERROR(m.MakeCurrent());
  // The resolve builds on the culling's list, so it runs only with it. With
  // it, the first draw at a camera is already the ID pass and a resolved
  // frame, so a look's pixels do not depend on how long the camera has been
  // still; without it, the culling's ID pass waits for the second draw (a
  // camera that moves every frame never pays for one).
  const bool want_table = m.cull_hidden && m.resolve;
  if (m.cull_hidden && m.triangle_count > 0 && (want_table || m.draws_at_camera >= 1) &&
      (!m.visible_valid || (want_table && !m.table_valid && !m.table_refused))) {
    RELIGHT_RETURN_IF_ERROR(m.DrawIdPass());
    RELIGHT_RETURN_IF_ERROR(m.FindVisibleTriangles());
    m.BuildTable();
  }
  if (want_table && m.table_valid) {
    m.Resolve(vertex_rgb8, out_rgb8);
    m.last_drawn_triangles = m.visible_count;
    m.last_resolved = true;
    return Status::Ok();
  }
  m.table_valid = false;  // llvmpipe draws over it
  m.last_resolved = false;
  const bool culled = m.cull_hidden && m.visible_valid;
  const uint32_t drawn = culled ? m.visible_count : m.triangle_count;
  m.LoadMatrices();
  glShadeModel(GL_SMOOTH);
  glClearColor(kBackgroundGrey, kBackgroundGrey, kBackgroundGrey, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  if (drawn > 0) {
    glBindBuffer(GL_ARRAY_BUFFER, m.color_vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, Bytes(m.vertex_count, 3), vertex_rgb8);
    glColorPointer(3, GL_UNSIGNED_BYTE, 0, nullptr);
    glBindBuffer(GL_ARRAY_BUFFER, m.position_vbo);
    glVertexPointer(3, GL_FLOAT, 0, nullptr);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, culled ? m.visible_index_vbo : m.index_vbo);
    render::DrawTriangleElements(drawn, culled ? drawn : render::kTrianglesPerScene);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, 0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
  }
  RELIGHT_RETURN_IF_ERROR(m.Finish("Draw"));
  m.last_drawn_triangles = drawn;
  if (m.draws_at_camera < 2) ++m.draws_at_camera;

  // OSMesa's buffer is bottom-up (OSMESA_Y_UP = 1); the output is top-down.
  const size_t w = static_cast<size_t>(m.width);
  for (int y = 0; y < m.height; ++y) {
    render::RgbaRowToRgb(m.color_rgba.data() + static_cast<size_t>(m.height - 1 - y) * w * 4, w,
                 out_rgb8 + static_cast<size_t>(y) * w * 3);
  }
  return Status::Ok();
}

Status OsMesaFrame::DrawTriangleIds(uint32_t* out_ids) {
  Impl& m = *impl_;
  if (out_ids == nullptr) return Status(StatusCode::kInvalidArgument, "render: DrawTriangleIds: null buffer");
  RELIGHT_RETURN_IF_ERROR(m.MakeCurrent());
  RELIGHT_RETURN_IF_ERROR(m.DrawIdPass());
  const size_t w = static_cast<size_t>(m.width);
  for (int y = 0; y < m.height; ++y) {
    const GLubyte* src = m.color_rgba.data() + static_cast<size_t>(m.height - 1 - y) * w * 4;
    uint32_t* dst = out_ids + static_cast<size_t>(y) * w;
    for (size_t x = 0; x < w; ++x) {
      const uint32_t code = render::TriangleCode(src + x * 4);
      dst[x] = code == 0 ? kNoTriangle : code - 1;
    }
  }
  // The pass is the culling's and the resolve's ID pass too: keep its list
  // and table for this camera.
  if (m.cull_hidden && m.triangle_count > 0) {
    RELIGHT_RETURN_IF_ERROR(m.FindVisibleTriangles());
    m.BuildTable();
  }
  return Status::Ok();
}

Status OsMesaFrame::UnprojectPixel(int x, int y, float out_world[3]) {
  Impl& m = *impl_;
  if (out_world == nullptr) return Status(StatusCode::kInvalidArgument, "render: UnprojectPixel: null output");
  RELIGHT_RETURN_IF_ERROR(m.MakeCurrent());
  if (!m.has_drawn) return Status(StatusCode::kInvalidArgument, "render: UnprojectPixel before any draw");
  if (x < 0 || y < 0 || x >= m.width || y >= m.height) {
    return Status(StatusCode::kInvalidArgument,
                  StrFormat("render: pixel (%d, %d) outside %dx%d", x, y, m.width, m.height));
  }
  GLfloat depth = 1.0f;
  glReadPixels(x, m.height - 1 - y, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, &depth);
  RELIGHT_RETURN_IF_ERROR(CheckGl("reading depth"));
  // The clear value: nothing was drawn under this pixel.
  if (!(depth < 1.0f)) {
    return Status(StatusCode::kNotFound, StrFormat("render: pixel (%d, %d) shows background", x, y));
  }
  double world_m[3];
  render::UnprojectDepth(m.drawn_camera, x, y, m.width, m.height, depth, world_m);
  for (int i = 0; i < 3; ++i) out_world[i] = static_cast<float>(world_m[i]);
  return Status::Ok();
}

}  // namespace relight
