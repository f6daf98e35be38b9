// Draws of every triangle go to llvmpipe in scenes of at most 2048
// triangles (scene_chunks.h kTrianglesPerScene), which bounds its bins at
// start-up: a mesh of three scenes and a bit, every triangle in view, must
// come out whole -- every triangle in the ID pass, and the first (chunked)
// colour draw the same pixels as the culled draws that follow, which send
// the visible triangles in one scene.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include "relight/render/osmesa_frame.h"

namespace relight {
namespace {

// A flat n x m grid of quads over [-1.6, 1.6] x [-1, 1] at z = 0, two
// triangles a quad.
BakeMesh GridMesh(int n, int m) {
  BakeMesh mesh;
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i <= n; ++i) {
      const double x = -1.6 + 3.2 * i / n, y = -1.0 + 2.0 * j / m;
      for (double v : {x, y, 0.0}) mesh.positions.push_back(static_cast<int32_t>(std::lround(v * 65536.0)));
    }
  }
  const auto at = [n](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      for (uint32_t v : {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)})
        mesh.triangles.push_back(v);
    }
  }
  return mesh;
}

TEST(OsMesaSceneChunks, EveryTriangleOfAChunkedDrawIsDrawn) {
  const BakeMesh mesh = GridMesh(64, 49);  // 6 272 triangles: 3 scenes of 2048 and one of 128
  const uint32_t triangles = mesh.triangle_count();
  ASSERT_GT(triangles, 3u * 2048u);
  constexpr int kW = 640, kH = 400;  // ~25 pixels a triangle
  CameraView view;
  view.position[2] = 2.0;  // looking straight down at the grid, which fills most of the frame
  view.target[2] = 0;
  view.fov_y_deg = 60;

  OsMesaFrame frame;
  ASSERT_TRUE(frame.Init(kW, kH, mesh).ok());
  frame.SetCamera(view);
  std::vector<uint32_t> ids(static_cast<size_t>(kW) * kH);
  ASSERT_TRUE(frame.DrawTriangleIds(ids.data()).ok());
  std::set<uint32_t> seen(ids.begin(), ids.end());
  seen.erase(0xFFFFFFFFu);  // background
  EXPECT_EQ(seen.size(), triangles) << "triangles missing from the ID pass";
  EXPECT_EQ(*seen.rbegin(), triangles - 1);  // the last scene's last triangle

  std::vector<uint8_t> colours(static_cast<size_t>(mesh.vertex_count()) * 3);
  std::mt19937 rng(5);
  for (uint8_t& c : colours) c = static_cast<uint8_t>(40 + rng() % 200);
  OsMesaFrame chunked, culled;
  ASSERT_TRUE(chunked.Init(kW, kH, mesh).ok());
  ASSERT_TRUE(culled.Init(kW, kH, mesh).ok());
  chunked.SetHiddenTriangleCulling(false);
  culled.SetStillCameraResolve(false);  // llvmpipe's pixels on both sides
  chunked.SetCamera(view);
  culled.SetCamera(view);
  std::vector<uint8_t> a(static_cast<size_t>(kW) * kH * 3), b(a.size());
  ASSERT_TRUE(chunked.Draw(colours.data(), a.data()).ok());
  for (int draw = 0; draw < 3; ++draw) ASSERT_TRUE(culled.Draw(colours.data(), b.data()).ok());
  EXPECT_EQ(culled.last_drawn_triangles(), triangles);  // all in view: one scene of them all
  EXPECT_EQ(chunked.last_drawn_triangles(), triangles);
  EXPECT_EQ(a, b) << "the chunked draw differs from the one-scene draw";
}

}  // namespace
}  // namespace relight
