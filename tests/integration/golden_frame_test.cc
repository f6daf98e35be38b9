// The rendered Cornell box against a committed golden PNG. On failure the
// actual frame and a diff image are written next to the test's temp dir.
// Regenerate after an intended change: RELIGHT_UPDATE_GOLDEN=1 ctest -R Golden
#include <vector>

#include <gtest/gtest.h>

#include "common/image_compare.h"
#include "cornell_fixture.h"
#include "relight/engine/engine.h"
#include "relight/render/osmesa_frame.h"
#include "relight/engine/tone_map.h"

namespace relight::test {
namespace {

TEST(GoldenFrame, CornellBoxMatchesGolden) {
  const BakedScene& baked = BakedFixture("cornell_box", baker::DirectModeKind::kExact);
  Engine engine;
  ASSERT_TRUE(engine.Open(baked.bake_path).ok());
  engine.Update();
  ToneMap tone_map;
  BuildToneMap(engine.bake().white_luminance, &tone_map);
  std::vector<uint8_t> vertex_rgb(engine.vertex_count() * 3);
  ToneMapRgb8(tone_map, engine.vertex_luminance(), vertex_rgb.data());

  constexpr int kWidth = 320, kHeight = 320;
  OsMesaFrame frame;
  ASSERT_TRUE(frame.Init(kWidth, kHeight, engine.bake().mesh).ok());
  const BakeCamera& cam = engine.bake().camera;
  CameraView view;
  for (int i = 0; i < 3; ++i) {
    view.position[i] = static_cast<float>(cam.position[i]) / 65536.0f;
    view.target[i] = static_cast<float>(cam.target[i]) / 65536.0f;
  }
  view.fov_y_deg = static_cast<float>(cam.fov_y) / 65536.0f;
  frame.SetCamera(view);
  std::vector<uint8_t> pixels(kWidth * kHeight * 3);
  ASSERT_TRUE(frame.Draw(vertex_rgb.data(), pixels.data()).ok());

  test_image::Tolerance tolerance;
  tolerance.channel_levels = 6;        // llvmpipe rasterisation and rounding drift
  tolerance.max_bad_fraction = 0.005;  // edge pixels
  EXPECT_TRUE(test_image::MatchesGoldenPng(std::string(RELIGHT_SOURCE_DIR) + "/tests/golden/cornell_box.png",
                                           {pixels.data(), kWidth, kHeight}, tolerance,
                                           ::testing::TempDir() + "/cornell_box"));
}

}  // namespace
}  // namespace relight::test
