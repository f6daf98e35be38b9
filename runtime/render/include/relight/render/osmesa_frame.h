// The renderer: an OSMesa (llvmpipe) context that draws the bake's mesh with
// per-vertex colours (Gouraud), and an ID pass that tells which triangle each
// pixel shows (picking, Dobashi 4.2). The GL side of the fence: floats here.
//
// Thread safety: one thread per OsMesaFrame; only one may be current at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/base/status.h"

namespace relight {

struct CameraView {
  float position[3] = {0, 0, 0};  // metres
  float target[3] = {0, 0, -1};   // metres
  float fov_y_deg = 50;
};

class OsMesaFrame {
 public:
  OsMesaFrame();
  ~OsMesaFrame();
  OsMesaFrame(const OsMesaFrame&) = delete;
  OsMesaFrame& operator=(const OsMesaFrame&) = delete;

  // Creates the context and uploads the mesh. kInvalidArgument for a zero or
  // oversized frame, kInternal if OSMesa refuses a context. Called again at
  // the same size, it keeps the context and its compiled shaders and only
  // replaces the mesh (a bad mesh then leaves the old one in place).
  Status Init(int width, int height, const BakeMesh& mesh);
  void SetCamera(const CameraView& camera);

  // Draws with 3 bytes of sRGB colour per vertex; out: width*height*3 bytes,
  // top row first.
  Status Draw(const uint8_t* vertex_rgb8, uint8_t* out_rgb8);
  // Triangle index per pixel (top row first), 0xFFFFFFFF where nothing is drawn.
  Status DrawTriangleIds(uint32_t* out_ids);
  // Hidden-triangle culling, on by default: from the second Draw at an
  // unchanged camera on (the first, with the resolve below), only the
  // triangles an ID pass found shown there are drawn; llvmpipe's frames are
  // bit-identical either way (src/visible_triangles.h). Off, there is no ID
  // pass and so no resolve.
  void SetHiddenTriangleCulling(bool on);
  // Still-camera resolve, on by default, with the culling: at the first Draw
  // at a camera an ID pass finds the shown triangles and keeps, per pixel,
  // its triangle and the weights of its vertices; that Draw and the later
  // ones at that camera compute each pixel from those and the vertex colours
  // instead of running llvmpipe's colour pass (src/pixel_resolve.h). Within
  // about one level of the rasterised pixel. A camera showing more than
  // 65 535 triangles gets the culled colour pass instead.
  void SetStillCameraResolve(bool on);
  // Triangles the last Draw showed: all of them, or the shown ones (drawn by
  // llvmpipe or resolved).
  uint32_t last_drawn_triangles() const;
  // Whether the last Draw came from the resolve's table rather than llvmpipe.
  bool last_draw_resolved() const;
  // Threads the resolve splits a frame's rows over (default 1, at most 16):
  // threads - 1 workers are started here (set-up time), joined at the next
  // change or in ~OsMesaFrame. The frame's bytes do not depend on it.
  void SetResolveThreads(int threads);
  // World point (metres) under pixel (x, y), from the depth buffer of the last
  // draw; kNotFound where the pixel shows background.
  Status UnprojectPixel(int x, int y, float out_world[3]);

  int width() const;
  int height() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// 8-bit RGB PNG files. Returns kIoError with the path and libpng's reason.
Status WritePngRgb8(const std::string& path, const uint8_t* rgb, int width, int height);
Status ReadPngRgb8(const std::string& path, std::vector<uint8_t>* rgb, int* width, int* height);

}  // namespace relight
