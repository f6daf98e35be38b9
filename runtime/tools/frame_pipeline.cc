#include "frame_pipeline.h"

#include "relight/base/clock.h"

namespace relight::cli {

CameraView CameraFromBake(const BakeCamera& cam) {
  CameraView view;
  for (int i = 0; i < 3; ++i) {
    view.position[i] = static_cast<float>(cam.position[i]) / 65536.0f;
    view.target[i] = static_cast<float>(cam.target[i]) / 65536.0f;
  }
  view.fov_y_deg = static_cast<float>(cam.fov_y) / 65536.0f;
  return view;
}

Status FramePipeline::WarmUp(int width, int height) {
  // One triangle across the view of the default camera (at the origin,
  // looking down -z), 2 m ahead.
  BakeMesh mesh;
  constexpr int32_t kMetre = 65536;
  mesh.positions = {-kMetre, -kMetre, -2 * kMetre, kMetre, -kMetre, -2 * kMetre, 0, kMetre, -2 * kMetre};
  mesh.triangles = {0, 1, 2};
  RELIGHT_RETURN_IF_ERROR(frame_.Init(width, height, mesh));
  frame_.SetCamera(CameraView{});
  const uint8_t rgb[9] = {200, 40, 40, 40, 200, 40, 40, 40, 200};
  std::vector<uint8_t> pixels(static_cast<size_t>(width) * height * 3);
  // The colour pass (which frames take when a camera shows more triangles
  // than the resolve names), then the ID pass (which the resolve takes).
  frame_.SetStillCameraResolve(false);
  RELIGHT_RETURN_IF_ERROR(frame_.Draw(rgb, pixels.data()));
  frame_.SetStillCameraResolve(true);
  return frame_.Draw(rgb, pixels.data());
}

Status FramePipeline::Init(const Engine& engine, int width, int height, const CameraView& view, int32_t white_q12) {
  BuildToneMap(white_q12 > 0 ? white_q12 : engine.bake().white_luminance, &tone_map_);
  RELIGHT_RETURN_IF_ERROR(frame_.Init(width, height, engine.bake().mesh));
  frame_.SetCamera(view);
  // The engine's threads wait while the frame is drawn: the resolve takes
  // as many (relightd --threads).
  frame_.SetResolveThreads(engine.thread_count());
  vertex_rgb_.assign(static_cast<size_t>(engine.vertex_count()) * 3, 0);
  pixels_.assign(static_cast<size_t>(width) * height * 3, 0);
  return Status::Ok();
}

Status FramePipeline::Render(Engine& engine) {
  const int64_t start_us = MonotonicUs();
  engine.Update();
  const int64_t updated_us = MonotonicUs();
  ToneMapRgb8(tone_map_, engine.vertex_luminance(), vertex_rgb_.data());
  const Status st = frame_.Draw(vertex_rgb_.data(), pixels_.data());
  last_update_us_ = updated_us - start_us;
  last_draw_us_ = MonotonicUs() - updated_us;
  return st;
}

}  // namespace relight::cli
