// The frame step shared by relight-render and relightd: engine state ->
// Update() -> tone map -> OSMesa draw -> an 8-bit RGB frame (top row first).
//
// Thread safety: one thread (OSMesa contexts are per thread).
#pragma once

#include <cstdint>
#include <vector>

#include "relight/engine/engine.h"
#include "relight/render/osmesa_frame.h"
#include "relight/engine/tone_map.h"

namespace relight::cli {

// The bake's camera as the renderer's floats.
CameraView CameraFromBake(const BakeCamera& camera);

class FramePipeline {
 public:
  // Has llvmpipe compile every shader the frames use, before any bake is
  // read: a stand-in triangle drawn as the frames draw (the colour pass, and
  // the ID pass the still-camera resolve takes instead). Init at the same size keeps
  // this context, so the frames compile nothing more, and the compiler's
  // pages can go back to the kernel before the bake comes in
  // (render/compiler_pages.h). Errors as Init's.
  Status WarmUp(int width, int height);
  // white_q12 <= 0: the bake's display white. kInvalidArgument / kInternal
  // from OsMesaFrame::Init.
  Status Init(const Engine& engine, int width, int height, const CameraView& view, int32_t white_q12);
  // Brings the engine up to date and draws; the frame is in pixels().
  Status Render(Engine& engine);
  // The last Render's parts, microseconds: Engine::Update, then tone map + draw.
  int64_t last_update_us() const { return last_update_us_; }
  int64_t last_draw_us() const { return last_draw_us_; }
  // Triangles the last draw showed (all, or those the camera shows: OsMesaFrame).
  uint32_t last_drawn_triangles() const { return frame_.last_drawn_triangles(); }
  // Whether the last draw was the still-camera resolve (OsMesaFrame).
  bool last_draw_resolved() const { return frame_.last_draw_resolved(); }

  const uint8_t* pixels() const { return pixels_.data(); }
  int width() const { return frame_.width(); }
  int height() const { return frame_.height(); }

 private:
  OsMesaFrame frame_;
  ToneMap tone_map_;
  std::vector<uint8_t> vertex_rgb_;
  std::vector<uint8_t> pixels_;
  int64_t last_update_us_ = 0, last_draw_us_ = 0;
};

}  // namespace relight::cli
