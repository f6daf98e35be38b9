// The OSMesa renderer against float64 references: Gouraud colours and
// triangle IDs per pixel from an analytic camera, unprojection against
// ray-plane intersection; PNG files; the golden-image comparison utility.
#include "relight/render/osmesa_frame.h"

#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <random>
#include <vector>

#include "common/image_compare.h"

namespace relight {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr uint32_t kNoTriangle = 0xFFFFFFFFu;
constexpr uint8_t kBackground = 32;  // the renderer's dark grey

int32_t ToQ16(double metres) { return static_cast<int32_t>(std::lround(metres * 65536.0)); }

void AddVertex(BakeMesh* mesh, double x, double y, double z) {
  mesh->positions.push_back(ToQ16(x));
  mesh->positions.push_back(ToQ16(y));
  mesh->positions.push_back(ToQ16(z));
}

// The square [-1, 1]^2 at z = 0 as triangles (0, 1, 2) and (0, 2, 3).
BakeMesh QuadMesh() {
  BakeMesh mesh;
  AddVertex(&mesh, -1, -1, 0);
  AddVertex(&mesh, 1, -1, 0);
  AddVertex(&mesh, 1, 1, 0);
  AddVertex(&mesh, -1, 1, 0);
  mesh.triangles = {0, 1, 2, 0, 2, 3};
  return mesh;
}

// Vertex colours of QuadMesh, one per corner.
const uint8_t kQuadRgb[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255};

// A float64 model of the camera the renderer promises: look-at with world +z
// up (+y for a vertical view), pixel centres, top row first.
struct RefCamera {
  double eye[3], right[3], up[3], fwd[3];
  double tan_half_fov, aspect;
  int width, height;
};

void Normalise(double v[3]) {
  const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  for (int i = 0; i < 3; ++i) v[i] /= len;
}

void Cross(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

RefCamera MakeRefCamera(const CameraView& view, int width, int height) {
  RefCamera c;
  for (int i = 0; i < 3; ++i) {
    c.eye[i] = view.position[i];
    c.fwd[i] = static_cast<double>(view.target[i]) - view.position[i];
  }
  Normalise(c.fwd);
  double world_up[3] = {0, 0, 1};
  if (std::fabs(c.fwd[2]) > 0.999) {
    world_up[1] = 1;
    world_up[2] = 0;
  }
  Cross(c.fwd, world_up, c.right);
  Normalise(c.right);
  Cross(c.right, c.fwd, c.up);
  c.tan_half_fov = std::tan(view.fov_y_deg * kPi / 360.0);
  c.aspect = static_cast<double>(width) / height;
  c.width = width;
  c.height = height;
  return c;
}

// Where the ray through the centre of pixel (x, y) meets the plane
// coordinate[axis] = 0. False when it runs parallel or behind the eye.
bool HitAxisPlane(const RefCamera& c, double x, double y, int axis, double out[3]) {
  const double sx = ((x + 0.5) / c.width * 2 - 1) * c.tan_half_fov * c.aspect;
  const double sy = (1 - (y + 0.5) / c.height * 2) * c.tan_half_fov;
  double dir[3];
  for (int i = 0; i < 3; ++i) dir[i] = c.fwd[i] + c.right[i] * sx + c.up[i] * sy;
  if (std::fabs(dir[axis]) < 1e-12) return false;
  const double t = -c.eye[axis] / dir[axis];
  if (t <= 0) return false;
  for (int i = 0; i < 3; ++i) out[i] = c.eye[i] + t * dir[i];
  return true;
}

// Metres on the plane per pixel near point p (for "stay a pixel away from edges").
double PixelFootprintM(const RefCamera& c, const double p[3]) {
  double d[3];
  for (int i = 0; i < 3; ++i) d[i] = p[i] - c.eye[i];
  const double dist = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  return dist * 2 * c.tan_half_fov / c.height;
}

// Gouraud reference on QuadMesh: linear interpolation of the vertex colours
// of the triangle holding (x, y), float64. Returns the triangle index.
int QuadGouraud(double x, double y, double out_rgb[3]) {
  const double vx[4] = {-1, 1, 1, -1};
  const double vy[4] = {-1, -1, 1, 1};
  const int tri[2][3] = {{0, 1, 2}, {0, 2, 3}};
  const int t = y <= x ? 0 : 1;
  const int* v = tri[t];
  const double det = (vx[v[1]] - vx[v[0]]) * (vy[v[2]] - vy[v[0]]) - (vx[v[2]] - vx[v[0]]) * (vy[v[1]] - vy[v[0]]);
  const double b1 = ((x - vx[v[0]]) * (vy[v[2]] - vy[v[0]]) - (vx[v[2]] - vx[v[0]]) * (y - vy[v[0]])) / det;
  const double b2 = ((vx[v[1]] - vx[v[0]]) * (y - vy[v[0]]) - (x - vx[v[0]]) * (vy[v[1]] - vy[v[0]])) / det;
  const double b0 = 1 - b1 - b2;
  for (int ch = 0; ch < 3; ++ch) {
    out_rgb[ch] = b0 * kQuadRgb[v[0] * 3 + ch] + b1 * kQuadRgb[v[1] * 3 + ch] + b2 * kQuadRgb[v[2] * 3 + ch];
  }
  return t;
}

CameraView HeadOnView() {
  CameraView view;
  view.position[2] = 3;  // 3 m above the quad, looking straight down (+y up)
  view.target[2] = 0;
  view.fov_y_deg = 60;
  return view;
}

constexpr int kW = 101;  // odd sizes: the centre pixel sits on the optical axis
constexpr int kH = 81;

std::string TempPath(const std::string& name) {
  return ::testing::TempDir() + "relight_render_" + std::to_string(getpid()) + "_" + name;
}

bool FileExists(const std::string& path) { return std::ifstream(path).good(); }

// An oblique view of QuadMesh: depth varies over the quad, so only a
// perspective-correct interpolation matches the float64 reference.
CameraView ObliqueView() {
  CameraView view;
  view.position[0] = 0.4f;
  view.position[1] = -2.5f;
  view.position[2] = 1.8f;
  view.fov_y_deg = 55;
  return view;
}

// One frame of QuadMesh against the float64 Gouraud reference: every pixel
// not at the silhouette within 2 levels, background outside; the pixel
// nearest each corner near its vertex colour. Returns the worst difference.
int CheckQuadFrame(const CameraView& view, const std::vector<uint8_t>& rgb, const std::string& what) {
  const RefCamera cam = MakeRefCamera(view, kW, kH);
  int checked_inside = 0, checked_outside = 0, worst = 0;
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      double p[3];
      if (!HitAxisPlane(cam, x, y, 2, p)) continue;  // above the horizon: background, as outside
      const double margin = 1.5 * PixelFootprintM(cam, p);
      const double edge = std::max(std::fabs(p[0]), std::fabs(p[1]));
      if (std::fabs(edge - 1) < margin) continue;  // silhouette pixels: coverage rule decides
      const uint8_t* px = &rgb[(y * kW + x) * 3];
      if (edge > 1) {
        for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(px[ch], kBackground) << what << " " << x << "," << y;
        ++checked_outside;
        continue;
      }
      double want[3];
      QuadGouraud(p[0], p[1], want);
      for (int ch = 0; ch < 3; ++ch) {
        const int diff = static_cast<int>(std::lround(std::fabs(px[ch] - want[ch])));
        worst = std::max(worst, diff);
        EXPECT_LE(diff, 2) << what << " pixel " << x << "," << y << " channel " << ch << " want " << want[ch];
      }
      ++checked_inside;
    }
  }
  EXPECT_GT(checked_inside, 1000) << what;
  EXPECT_GT(checked_outside, 1000) << what;
  std::printf("Gouraud quad, %s: %d inside / %d background pixels, worst %d levels\n", what.c_str(),
              checked_inside, checked_outside, worst);

  // The pixel nearest each corner, inside the quad, is its vertex colour up
  // to the colour gradient (at most 255 levels over 2 m per axis) times the
  // pixel centre's offset from the vertex, plus rounding.
  const double corner_xy[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  for (int v = 0; v < 4; ++v) {
    int best_x = -1, best_y = -1;
    double best_offset_m = 1e9;
    for (int y = 0; y < kH; ++y) {
      for (int x = 0; x < kW; ++x) {
        double p[3];
        if (!HitAxisPlane(cam, x, y, 2, p)) continue;
        if (std::max(std::fabs(p[0]), std::fabs(p[1])) >= 1) continue;
        const double offset_m = std::fabs(p[0] - corner_xy[v][0]) + std::fabs(p[1] - corner_xy[v][1]);
        if (offset_m < best_offset_m) {
          best_offset_m = offset_m;
          best_x = x;
          best_y = y;
        }
      }
    }
    const double bound = 255.0 / 2.0 * best_offset_m + 2;
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_NEAR(rgb[(best_y * kW + best_x) * 3 + ch], kQuadRgb[v * 3 + ch], bound) << what << " corner " << v;
    }
  }
  return worst;
}

// Head-on and oblique, llvmpipe's colour pass and the still-camera resolve,
// two draws each, all against the same reference.
TEST(OsMesaFrameTest, GouraudQuadMatchesFloat64Reference) {
  for (const CameraView& view : {HeadOnView(), ObliqueView()}) {
    for (bool resolve : {false, true}) {
    OsMesaFrame frame;
    ASSERT_TRUE(frame.Init(kW, kH, QuadMesh()).ok());
    frame.SetStillCameraResolve(resolve);
    frame.SetCamera(view);
    std::vector<uint8_t> rgb(kW * kH * 3);
    for (int draw = 0; draw < 2; ++draw) {
      ASSERT_TRUE(frame.Draw(kQuadRgb, rgb.data()).ok());
      EXPECT_EQ(frame.last_draw_resolved(), resolve);
      const std::string what = std::string(view.position[0] == 0 ? "head-on" : "oblique") +
                               (resolve ? ", resolved" : ", llvmpipe");
      CheckQuadFrame(view, rgb, what);
      if (view.position[0] == 0) {
        // The centre lies on the shared diagonal: the mean of corners 0 and 2.
        const uint8_t* centre = &rgb[((kH / 2) * kW + kW / 2) * 3];
        EXPECT_NEAR(centre[0], 127.5, 2) << what;
        EXPECT_NEAR(centre[1], 0, 2) << what;
        EXPECT_NEAR(centre[2], 127.5, 2) << what;
      }
    }
    }
  }
}

TEST(OsMesaFrameTest, TriangleIdsMatchReferenceAndBackgroundIsAllOnes) {
  OsMesaFrame frame;
  ASSERT_TRUE(frame.Init(kW, kH, QuadMesh()).ok());
  frame.SetCamera(HeadOnView());
  std::vector<uint32_t> ids(kW * kH, 12345);
  ASSERT_TRUE(frame.DrawTriangleIds(ids.data()).ok());

  const RefCamera cam = MakeRefCamera(HeadOnView(), kW, kH);
  int counts[3] = {0, 0, 0};
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      double p[3];
      ASSERT_TRUE(HitAxisPlane(cam, x, y, 2, p));
      const double margin = 1.5 * PixelFootprintM(cam, p);
      const double edge = std::max(std::fabs(p[0]), std::fabs(p[1]));
      // Near the silhouette or the shared diagonal the coverage rule decides.
      if (std::fabs(edge - 1) < margin || std::fabs(p[1] - p[0]) < 1.5 * margin) continue;
      const uint32_t got = ids[y * kW + x];
      if (edge > 1) {
        ASSERT_EQ(got, kNoTriangle) << x << "," << y;
        ++counts[2];
      } else {
        double unused[3];
        const uint32_t want = static_cast<uint32_t>(QuadGouraud(p[0], p[1], unused));
        ASSERT_EQ(got, want) << x << "," << y;
        ++counts[want];
      }
    }
  }
  EXPECT_GT(counts[0], 500);
  EXPECT_GT(counts[1], 500);
  EXPECT_GT(counts[2], 1000);
  // Spot checks: lower right half is triangle 0, upper left triangle 1.
  EXPECT_EQ(ids[(kH / 2 + 10) * kW + kW / 2 + 10], 0u);
  EXPECT_EQ(ids[(kH / 2 - 10) * kW + kW / 2 - 10], 1u);
  EXPECT_EQ(ids[0], kNoTriangle);
}

TEST(OsMesaFrameTest, UnprojectPixelLandsOnTheQuadPlaneWithinOneCentimetre) {
  // An oblique view, so depth is not constant over the quad.
  CameraView view;
  view.position[0] = 0.4f;
  view.position[1] = -2.5f;
  view.position[2] = 1.8f;
  view.target[0] = 0;
  view.target[1] = 0;
  view.target[2] = 0;
  view.fov_y_deg = 55;
  OsMesaFrame frame;
  ASSERT_TRUE(frame.Init(kW, kH, QuadMesh()).ok());
  frame.SetCamera(view);
  std::vector<uint8_t> rgb(kW * kH * 3);
  ASSERT_TRUE(frame.Draw(kQuadRgb, rgb.data()).ok());
  // Moving the camera after the draw must not change what the depth means.
  CameraView elsewhere = view;
  elsewhere.position[2] = 5;
  frame.SetCamera(elsewhere);

  const RefCamera cam = MakeRefCamera(view, kW, kH);
  int checked = 0, background = 0;
  double worst_m = 0;
  for (int y = 0; y < kH; y += 2) {
    for (int x = 0; x < kW; x += 2) {
      double p[3];
      const bool hits = HitAxisPlane(cam, x, y, 2, p);
      const double edge = hits ? std::max(std::fabs(p[0]), std::fabs(p[1])) : 2;
      if (hits && std::fabs(edge - 1) < 2 * PixelFootprintM(cam, p)) continue;
      float world[3];
      const Status st = frame.UnprojectPixel(x, y, world);
      if (edge > 1) {
        ASSERT_EQ(st.code(), StatusCode::kNotFound) << x << "," << y;
        ++background;
        continue;
      }
      ASSERT_TRUE(st.ok()) << st.ToString();
      double err2 = 0;
      for (int i = 0; i < 3; ++i) err2 += (world[i] - p[i]) * (world[i] - p[i]);
      worst_m = std::max(worst_m, std::sqrt(err2));
      EXPECT_NEAR(world[2], 0.0, 0.01) << x << "," << y;
      ++checked;
    }
  }
  EXPECT_GT(checked, 200);
  EXPECT_GT(background, 100);
  EXPECT_LT(worst_m, 0.01);
  std::printf("Unproject: %d pixels, worst distance to the ray-plane hit %.2e m\n", checked, worst_m);

  float world[3];
  EXPECT_EQ(frame.UnprojectPixel(-1, 0, world).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(frame.UnprojectPixel(0, kH, world).code(), StatusCode::kInvalidArgument);
}

TEST(OsMesaFrameTest, UnprojectBeforeAnyDrawIsAnError) {
  OsMesaFrame frame;
  ASSERT_TRUE(frame.Init(8, 8, QuadMesh()).ok());
  float world[3];
  EXPECT_EQ(frame.UnprojectPixel(4, 4, world).code(), StatusCode::kInvalidArgument);
}

// Bounding box of pixels that are not background.
struct Coverage {
  int min_x = 1 << 30, max_x = -1, min_y = 1 << 30, max_y = -1, count = 0;
};

Coverage CoverageOf(const std::vector<uint8_t>& rgb, int width, int height) {
  Coverage c;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const uint8_t* px = &rgb[(y * width + x) * 3];
      if (px[0] == kBackground && px[1] == kBackground && px[2] == kBackground) continue;
      c.min_x = std::min(c.min_x, x);
      c.max_x = std::max(c.max_x, x);
      c.min_y = std::min(c.min_y, y);
      c.max_y = std::max(c.max_y, y);
      ++c.count;
    }
  }
  return c;
}

TEST(OsMesaFrameTest, ImageIsTopRowFirstAndNotMirrored) {
  // A triangle in the upper-right quadrant of the view, seen with world +z up:
  // the wall y = 0 seen from y = -3, so up in the image is +z and right is +x.
  BakeMesh mesh;
  AddVertex(&mesh, 0.3, 0, 0.3);
  AddVertex(&mesh, 1.0, 0, 0.3);
  AddVertex(&mesh, 0.6, 0, 1.0);
  mesh.triangles = {0, 1, 2};
  const uint8_t white[9] = {255, 255, 255, 255, 255, 255, 255, 255, 255};
  CameraView view;
  view.position[0] = 0;
  view.position[1] = -3;
  view.position[2] = 0;
  view.target[0] = 0;
  view.target[1] = 0;
  view.target[2] = 0;
  view.fov_y_deg = 60;

  OsMesaFrame frame;
  ASSERT_TRUE(frame.Init(kW, kH, mesh).ok());
  frame.SetCamera(view);
  std::vector<uint8_t> rgb(kW * kH * 3);
  ASSERT_TRUE(frame.Draw(white, rgb.data()).ok());
  const Coverage c = CoverageOf(rgb, kW, kH);
  ASSERT_GT(c.count, 50);
  EXPECT_LT(c.max_y, kH / 2);  // only in the top half
  EXPECT_GT(c.min_x, kW / 2);  // only in the right half
  // The apex (z = 1 m) is the topmost point: its row from the reference camera.
  const RefCamera cam = MakeRefCamera(view, kW, kH);
  const double apex_row = (1 - 1.0 / (3 * cam.tan_half_fov)) * kH / 2;
  EXPECT_NEAR(c.min_y, apex_row, 1.5);
}

TEST(OsMesaFrameTest, InitRejectsBadSizesAndMeshesWithAStatus) {
  OsMesaFrame frame;
  std::vector<uint8_t> rgb(16 * 16 * 3);
  // Not initialised: an error, not a crash.
  EXPECT_EQ(frame.Draw(kQuadRgb, rgb.data()).code(), StatusCode::kInvalidArgument);

  EXPECT_EQ(frame.Init(0, 0, QuadMesh()).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(frame.Init(-4, 16, QuadMesh()).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(frame.Init(16, 100000, QuadMesh()).code(), StatusCode::kInvalidArgument);
  BakeMesh bad = QuadMesh();
  bad.triangles[4] = 4;  // one past the last vertex
  const Status st = frame.Init(16, 16, bad);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("vertex 4"), std::string::npos) << st.message();
  bad = QuadMesh();
  bad.positions.pop_back();
  EXPECT_EQ(frame.Init(16, 16, bad).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(frame.width(), 0);
  EXPECT_EQ(frame.Draw(kQuadRgb, rgb.data()).code(), StatusCode::kInvalidArgument);

  // The same object still works after failures, and re-initialises cleanly.
  ASSERT_TRUE(frame.Init(16, 16, QuadMesh()).ok());
  frame.SetCamera(HeadOnView());
  EXPECT_TRUE(frame.Draw(kQuadRgb, rgb.data()).ok());
  EXPECT_EQ(frame.Draw(nullptr, rgb.data()).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(frame.Init(16, 16, QuadMesh()).ok());
  EXPECT_EQ(frame.width(), 16);
  EXPECT_EQ(frame.height(), 16);
}

TEST(OsMesaFrameTest, EmptyMeshDrawsOnlyBackground) {
  OsMesaFrame frame;
  ASSERT_TRUE(frame.Init(9, 7, BakeMesh()).ok());
  std::vector<uint8_t> rgb(9 * 7 * 3, 0);
  ASSERT_TRUE(frame.Draw(nullptr, rgb.data()).ok());
  for (uint8_t v : rgb) ASSERT_EQ(v, kBackground);
  std::vector<uint32_t> ids(9 * 7, 0);
  ASSERT_TRUE(frame.DrawTriangleIds(ids.data()).ok());
  for (uint32_t id : ids) ASSERT_EQ(id, kNoTriangle);
}

// A closed box room, each face split into a grid of quads of about cell_m.
BakeMesh RoomMesh(double sx, double sy, double sz, double cell_m) {
  BakeMesh mesh;
  // Each face: origin, two edge vectors.
  const double faces[6][9] = {
      {0, 0, 0, sx, 0, 0, 0, sy, 0},   {0, 0, sz, sx, 0, 0, 0, sy, 0},  // floor, ceiling
      {0, 0, 0, sx, 0, 0, 0, 0, sz},   {0, sy, 0, sx, 0, 0, 0, 0, sz},  // walls y = 0, y = sy
      {0, 0, 0, 0, sy, 0, 0, 0, sz},   {sx, 0, 0, 0, sy, 0, 0, 0, sz},  // walls x = 0, x = sx
  };
  for (const auto& f : faces) {
    const double len_u = std::sqrt(f[3] * f[3] + f[4] * f[4] + f[5] * f[5]);
    const double len_v = std::sqrt(f[6] * f[6] + f[7] * f[7] + f[8] * f[8]);
    const int nu = std::max(1, static_cast<int>(std::lround(len_u / cell_m)));
    const int nv = std::max(1, static_cast<int>(std::lround(len_v / cell_m)));
    const uint32_t base = mesh.vertex_count();
    for (int j = 0; j <= nv; ++j) {
      for (int i = 0; i <= nu; ++i) {
        const double u = static_cast<double>(i) / nu, v = static_cast<double>(j) / nv;
        AddVertex(&mesh, f[0] + u * f[3] + v * f[6], f[1] + u * f[4] + v * f[7], f[2] + u * f[5] + v * f[8]);
      }
    }
    for (int j = 0; j < nv; ++j) {
      for (int i = 0; i < nu; ++i) {
        const uint32_t a = base + static_cast<uint32_t>(j * (nu + 1) + i);
        const uint32_t b = a + 1, c = a + static_cast<uint32_t>(nu + 1), d = c + 1;
        mesh.triangles.insert(mesh.triangles.end(), {a, b, d, a, d, c});
      }
    }
  }
  return mesh;
}

// A camera at (p[0], p[1], p[2]) m looking at (p[3], p[4], p[5]) m.
CameraView ViewFrom(const float (&p)[6], float fov_y_deg) {
  CameraView view;
  for (int i = 0; i < 3; ++i) {
    view.position[i] = p[i];
    view.target[i] = p[3 + i];
  }
  view.fov_y_deg = fov_y_deg;
  return view;
}

// Not a timed assertion: it checks full coverage from inside a closed room
// and prints the frame time for the ~50k-triangle, 1280x720 case.
TEST(OsMesaFrameTest, RoomFromInsideCoversEveryPixelAndReportsFrameTime) {
  const BakeMesh mesh = RoomMesh(6, 4, 3, 0.0655);
  const uint32_t vertices = mesh.vertex_count();
  const uint32_t triangles = mesh.triangle_count();
  ASSERT_GT(triangles, 45000u);
  ASSERT_LT(triangles, 55000u);
  std::vector<uint8_t> colours(static_cast<size_t>(vertices) * 3);
  for (uint32_t v = 0; v < vertices; ++v) {
    // Never the background grey: every channel at least 64.
    for (int ch = 0; ch < 3; ++ch) {
      const double m = mesh.positions[v * 3 + ch] / 65536.0;
      colours[v * 3 + ch] = static_cast<uint8_t>(64 + static_cast<int>(m * 30) % 190);
    }
  }
  constexpr int kWidth = 1280, kHeight = 720;
  OsMesaFrame frame;
  ASSERT_TRUE(frame.Init(kWidth, kHeight, mesh).ok());
  frame.SetCamera(ViewFrom({1, 1, 1.6f, 5, 3, 1.0f}, 60));

  std::vector<uint8_t> rgb(static_cast<size_t>(kWidth) * kHeight * 3);
  std::vector<uint32_t> ids(static_cast<size_t>(kWidth) * kHeight);
  ASSERT_TRUE(frame.Draw(colours.data(), rgb.data()).ok());  // warm-up (shader compile)
  ASSERT_TRUE(frame.DrawTriangleIds(ids.data()).ok());
  for (uint32_t id : ids) ASSERT_LT(id, triangles);
  EXPECT_EQ(CoverageOf(rgb, kWidth, kHeight).count, kWidth * kHeight);

  // Picking: the point under a pixel lies on the plane of the triangle the
  // ID pass names there (depth error grows as z^2: the far wall is ~5 m away).
  double worst_m = 0;
  for (int y = 5; y < kHeight; y += 37) {
    for (int x = 5; x < kWidth; x += 37) {
      float p[3];
      ASSERT_TRUE(frame.UnprojectPixel(x, y, p).ok());
      const uint32_t t = ids[static_cast<size_t>(y) * kWidth + x];
      double v[3][3];
      for (int k = 0; k < 3; ++k) {
        for (int a = 0; a < 3; ++a) v[k][a] = mesh.positions[mesh.triangles[t * 3 + k] * 3 + a] / 65536.0;
      }
      const double e1[3] = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
      const double e2[3] = {v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
      double n[3];
      Cross(e1, e2, n);
      Normalise(n);
      const double dist_m = std::fabs((p[0] - v[0][0]) * n[0] + (p[1] - v[0][1]) * n[1] + (p[2] - v[0][2]) * n[2]);
      worst_m = std::max(worst_m, dist_m);
    }
  }
  EXPECT_LT(worst_m, 0.01);
  std::printf("Room picking: worst distance from the picked triangle's plane %.2e m\n", worst_m);

  constexpr int kFrames = 20;
  using Clock = std::chrono::steady_clock;
  auto t0 = Clock::now();
  for (int i = 0; i < kFrames; ++i) {
    colours[static_cast<size_t>(i) * 3] = static_cast<uint8_t>(100 + i);  // a new frame's colours
    ASSERT_TRUE(frame.Draw(colours.data(), rgb.data()).ok());
  }
  auto t1 = Clock::now();
  for (int i = 0; i < kFrames; ++i) ASSERT_TRUE(frame.DrawTriangleIds(ids.data()).ok());
  auto t2 = Clock::now();
  const double draw_ms = std::chrono::duration<double, std::milli>(t1 - t0).count() / kFrames;
  const double ids_ms = std::chrono::duration<double, std::milli>(t2 - t1).count() / kFrames;
  const char* threads = std::getenv("LP_NUM_THREADS");
  std::printf("Room %u triangles, %u vertices, %dx%d, LP_NUM_THREADS=%s: Draw %.1f ms/frame, "
              "DrawTriangleIds %.1f ms/frame (mean of %d)\n",
              triangles, vertices, kWidth, kHeight, threads != nullptr ? threads : "(unset)", draw_ms, ids_ms,
              kFrames);
}

// Hidden-triangle culling (visible_triangles.h) changes no pixel: a room
// with a box in it, seen from several places inside, each camera drawn three
// times with new colours (all triangles, then the ID pass and the shown
// ones, then the shown ones) against a frame that never culls; a picking
// pass at a new camera hands its list to the next Draw.
// The 6 x 4 x 3 m room with a 1 x 1 x 1.2 m box standing in it, and four
// places inside to look from (eye, then target).
BakeMesh RoomWithABox() {
  BakeMesh mesh = RoomMesh(6, 4, 3, 0.2);
  const BakeMesh box = RoomMesh(1, 1, 1.2, 0.1);
  const uint32_t offset = mesh.vertex_count();
  for (uint32_t v = 0; v < box.vertex_count(); ++v) {
    AddVertex(&mesh, box.positions[v * 3] / 65536.0 + 2.5, box.positions[v * 3 + 1] / 65536.0 + 1.5,
              box.positions[v * 3 + 2] / 65536.0);
  }
  for (uint32_t i : box.triangles) mesh.triangles.push_back(i + offset);
  return mesh;
}

constexpr float kPlacesInTheRoom[4][6] = {{0.5f, 0.5f, 1.6f, 5, 3, 0.8f},
                                          {5.5f, 3.5f, 2.5f, 2.8f, 1.8f, 0.3f},
                                          {3.0f, 0.3f, 1.0f, 3.0f, 3.9f, 0.6f},
                                          {1.0f, 3.0f, 0.2f, 3.2f, 1.6f, 2.9f}};

TEST(OsMesaFrameTest, HiddenTriangleCullingDrawsFewerTrianglesAndTheSamePixels) {
  const BakeMesh mesh = RoomWithABox();
  const uint32_t triangles = mesh.triangle_count();
  std::vector<uint8_t> colours(static_cast<size_t>(mesh.vertex_count()) * 3);
  std::mt19937 rng(11);

  constexpr int kFrameW = 320, kFrameH = 200;
  OsMesaFrame culled, plain;
  ASSERT_TRUE(culled.Init(kFrameW, kFrameH, mesh).ok());
  ASSERT_TRUE(plain.Init(kFrameW, kFrameH, mesh).ok());
  plain.SetHiddenTriangleCulling(false);
  culled.SetStillCameraResolve(false);  // llvmpipe's pixels on both sides
  std::vector<uint8_t> a(static_cast<size_t>(kFrameW) * kFrameH * 3), b(a.size());
  uint32_t fewest = triangles;
  for (const auto& p : kPlacesInTheRoom) {
    const CameraView view = ViewFrom(p, 60);
    culled.SetCamera(view);
    plain.SetCamera(view);
    for (int draw = 0; draw < 3; ++draw) {
      for (uint8_t& c : colours) c = static_cast<uint8_t>(64 + rng() % 190);
      ASSERT_TRUE(culled.Draw(colours.data(), a.data()).ok());
      ASSERT_TRUE(plain.Draw(colours.data(), b.data()).ok());
      ASSERT_EQ(a, b) << "camera at " << p[0] << ", " << p[1] << ", " << p[2] << ", draw " << draw;
      EXPECT_EQ(plain.last_drawn_triangles(), triangles);
      if (draw == 0) {
        EXPECT_EQ(culled.last_drawn_triangles(), triangles);  // the first at a camera draws all
      } else {
        EXPECT_LT(culled.last_drawn_triangles(), triangles);  // the wall behind the camera is hidden
        EXPECT_GT(culled.last_drawn_triangles(), 0u);
      }
    }
    fewest = std::min(fewest, culled.last_drawn_triangles());
    // The same camera again keeps the list; a picking pass at a new one makes it.
    culled.SetCamera(view);
    ASSERT_TRUE(culled.Draw(colours.data(), a.data()).ok());
    EXPECT_LT(culled.last_drawn_triangles(), triangles);
  }
  std::printf("Culling: %u triangles, fewest drawn %u\n", triangles, fewest);

  const CameraView above = ViewFrom({4.0f, 2.0f, 2.8f, 3.0f, 2.0f, 0.0f}, 50);
  culled.SetCamera(above);
  plain.SetCamera(above);
  std::vector<uint32_t> ids(static_cast<size_t>(kFrameW) * kFrameH);
  ASSERT_TRUE(culled.DrawTriangleIds(ids.data()).ok());
  ASSERT_TRUE(culled.Draw(colours.data(), a.data()).ok());
  ASSERT_TRUE(plain.Draw(colours.data(), b.data()).ok());
  EXPECT_EQ(a, b);
  EXPECT_LT(culled.last_drawn_triangles(), triangles);
}

// The still-camera resolve (pixel_resolve.h) against llvmpipe's own frames:
// the room with a box from four places inside, three draws each with new
// random colours, every one resolved (the first at a camera too), within one
// level of llvmpipe's on nearly every pixel. A picking pass at a new camera hands its table to the next Draw, and
// the depth under a pixel still comes from that camera after resolved frames.
TEST(OsMesaFrameTest, StillCameraResolveMatchesTheRasterisedFrameWithinALevel) {
  const BakeMesh mesh = RoomWithABox();
  std::vector<uint8_t> colours(static_cast<size_t>(mesh.vertex_count()) * 3);
  std::mt19937 rng(23);

  constexpr int kFrameW = 320, kFrameH = 200;
  OsMesaFrame resolved, rasterised;
  ASSERT_TRUE(resolved.Init(kFrameW, kFrameH, mesh).ok());
  ASSERT_TRUE(rasterised.Init(kFrameW, kFrameH, mesh).ok());
  rasterised.SetStillCameraResolve(false);
  std::vector<uint8_t> a(static_cast<size_t>(kFrameW) * kFrameH * 3), b(a.size());
  size_t compared = 0, over_one = 0;
  int worst = 0;
  double sum = 0;
  const auto compare = [&](const std::string& what) {
    for (size_t i = 0; i < a.size(); ++i) {
      const int d = std::abs(static_cast<int>(a[i]) - static_cast<int>(b[i]));
      worst = std::max(worst, d);
      sum += d;
      over_one += d > 1 ? 1 : 0;
      EXPECT_LE(d, 2) << what << " byte " << i;
      if (d > 2) return;
    }
    compared += a.size();
  };
  for (const auto& p : kPlacesInTheRoom) {
    const CameraView view = ViewFrom(p, 60);
    resolved.SetCamera(view);
    rasterised.SetCamera(view);
    for (int draw = 0; draw < 3; ++draw) {
      for (uint8_t& c : colours) c = static_cast<uint8_t>(rng() % 256);
      ASSERT_TRUE(resolved.Draw(colours.data(), a.data()).ok());
      ASSERT_TRUE(rasterised.Draw(colours.data(), b.data()).ok());
      EXPECT_TRUE(resolved.last_draw_resolved()) << "draw " << draw;
      EXPECT_FALSE(rasterised.last_draw_resolved());
      if (draw > 0) {
        EXPECT_EQ(resolved.last_drawn_triangles(), rasterised.last_drawn_triangles());
      }
      compare("camera at " + std::to_string(p[0]) + ", " + std::to_string(p[1]) + ", draw " +
              std::to_string(draw));
    }
  }
  ASSERT_GT(compared, 0u);
  const double mean = sum / static_cast<double>(compared);
  std::printf("Resolve against llvmpipe: %zu channel values, worst %d levels, mean %.3f, %.4f %% over one\n",
              compared, worst, mean, 100.0 * static_cast<double>(over_one) / static_cast<double>(compared));
  EXPECT_LT(mean, 0.25);
  EXPECT_LE(static_cast<double>(over_one), 0.0005 * static_cast<double>(compared));

  // Picking at a new camera: its ID pass is the table, which the next Draw takes.
  const CameraView above = ViewFrom({4.0f, 2.0f, 2.8f, 3.0f, 2.0f, 0.0f}, 50);
  resolved.SetCamera(above);
  rasterised.SetCamera(above);
  std::vector<uint32_t> ids(static_cast<size_t>(kFrameW) * kFrameH);
  ASSERT_TRUE(resolved.DrawTriangleIds(ids.data()).ok());
  ASSERT_TRUE(rasterised.DrawTriangleIds(ids.data()).ok());
  ASSERT_TRUE(resolved.Draw(colours.data(), a.data()).ok());
  ASSERT_TRUE(rasterised.Draw(colours.data(), b.data()).ok());
  EXPECT_TRUE(resolved.last_draw_resolved());
  compare("after picking");
  float at_resolved[3], at_rasterised[3];
  ASSERT_TRUE(resolved.UnprojectPixel(kFrameW / 2, kFrameH / 2, at_resolved).ok());
  ASSERT_TRUE(rasterised.UnprojectPixel(kFrameW / 2, kFrameH / 2, at_rasterised).ok());
  for (int i = 0; i < 3; ++i) EXPECT_EQ(at_resolved[i], at_rasterised[i]);

  // Turned off, the next Draw is llvmpipe's again, and at the same camera
  // turned back on, the one after is resolved again.
  resolved.SetStillCameraResolve(false);
  ASSERT_TRUE(resolved.Draw(colours.data(), a.data()).ok());
  EXPECT_FALSE(resolved.last_draw_resolved());
  EXPECT_EQ(a, b);
  resolved.SetStillCameraResolve(true);
  ASSERT_TRUE(resolved.Draw(colours.data(), a.data()).ok());
  EXPECT_TRUE(resolved.last_draw_resolved());
  compare("turned on again");
}

// The resolve's rows split over 2 and 3 threads give one thread's frame, byte
// for byte, at an odd height (uneven splits), from three places in the room.
TEST(OsMesaFrameTest, TheResolveSplitOverThreadsWritesTheSameFrame) {
  const BakeMesh mesh = RoomMesh(6, 4, 3, 0.2);
  constexpr int kFrameW = 317, kFrameH = 203;
  OsMesaFrame one, split;
  ASSERT_TRUE(one.Init(kFrameW, kFrameH, mesh).ok());
  ASSERT_TRUE(split.Init(kFrameW, kFrameH, mesh).ok());
  std::vector<uint8_t> colours(static_cast<size_t>(mesh.vertex_count()) * 3);
  std::mt19937 rng(31);
  std::vector<uint8_t> a(static_cast<size_t>(kFrameW) * kFrameH * 3), b(a.size());
  const float places[3][6] = {{0.5f, 0.5f, 1.6f, 5, 3, 0.8f}, {5.5f, 3.5f, 2.5f, 2.8f, 1.8f, 0.3f},
                              {3.0f, 2.0f, 2.9f, 3.0f, 2.0f, 0.0f}};
  for (int threads : {2, 3, 1, 2}) {
    split.SetResolveThreads(threads);
    for (const auto& p : places) {
      one.SetCamera(ViewFrom(p, 60));
      split.SetCamera(ViewFrom(p, 60));
      for (uint8_t& c : colours) c = static_cast<uint8_t>(rng() % 256);
      ASSERT_TRUE(one.Draw(colours.data(), a.data()).ok());
      ASSERT_TRUE(split.Draw(colours.data(), b.data()).ok());
      ASSERT_TRUE(split.last_draw_resolved());
      ASSERT_EQ(a, b) << threads << " threads, camera at " << p[0] << ", " << p[1];
    }
  }
}

// A camera that shows more triangles than a table can name (65 535) keeps
// llvmpipe's culled draw, with its exact pixels, and no ID pass per frame.
TEST(OsMesaFrameTest, ACameraShowingMoreTrianglesThanATableNamesIsRasterised) {
  BakeMesh mesh;
  constexpr int kN = 240, kM = 140;  // 67 200 triangles over [-1.6, 1.6] x [-1, 1]
  for (int j = 0; j <= kM; ++j) {
    for (int i = 0; i <= kN; ++i) AddVertex(&mesh, -1.6 + 3.2 * i / kN, -1.0 + 2.0 * j / kM, 0);
  }
  for (int j = 0; j < kM; ++j) {
    for (int i = 0; i < kN; ++i) {
      const uint32_t v = static_cast<uint32_t>(j * (kN + 1) + i), up = v + kN + 1;
      mesh.triangles.insert(mesh.triangles.end(), {v, v + 1, up + 1, v, up + 1, up});
    }
  }
  CameraView view;
  view.position[2] = 1.9f;
  view.fov_y_deg = 60;
  constexpr int kFrameW = 1280, kFrameH = 720;
  OsMesaFrame frame, plain;
  ASSERT_TRUE(frame.Init(kFrameW, kFrameH, mesh).ok());
  ASSERT_TRUE(plain.Init(kFrameW, kFrameH, mesh).ok());
  plain.SetStillCameraResolve(false);
  frame.SetCamera(view);
  plain.SetCamera(view);
  std::vector<uint8_t> colours(static_cast<size_t>(mesh.vertex_count()) * 3);
  std::mt19937 rng(3);
  std::vector<uint8_t> a(static_cast<size_t>(kFrameW) * kFrameH * 3), b(a.size());
  for (int draw = 0; draw < 3; ++draw) {
    for (uint8_t& c : colours) c = static_cast<uint8_t>(rng() % 256);
    ASSERT_TRUE(frame.Draw(colours.data(), a.data()).ok());
    ASSERT_TRUE(plain.Draw(colours.data(), b.data()).ok());
    EXPECT_FALSE(frame.last_draw_resolved()) << "draw " << draw;
    ASSERT_EQ(a, b) << "draw " << draw;
  }
  EXPECT_GT(frame.last_drawn_triangles(), 65535u);
}

// Init again at the same size keeps the context (its compiled shaders) and
// replaces the mesh: every frame, ID pass and culled draw is then the same as
// a fresh frame's. A bad mesh leaves the loaded one; a new size, a new context.
TEST(OsMesaFrameTest, ANewMeshAtTheSameSizeDrawsLikeAFreshFrame) {
  const BakeMesh room = RoomMesh(6, 4, 3, 0.25);
  constexpr int kFrameW = 160, kFrameH = 100;
  OsMesaFrame reused, fresh;
  std::vector<uint8_t> a(static_cast<size_t>(kFrameW) * kFrameH * 3), b(a.size());
  ASSERT_TRUE(reused.Init(kFrameW, kFrameH, QuadMesh()).ok());
  reused.SetCamera(HeadOnView());
  for (int draw = 0; draw < 2; ++draw) ASSERT_TRUE(reused.Draw(kQuadRgb, a.data()).ok());
  EXPECT_EQ(reused.last_drawn_triangles(), 2u);

  ASSERT_TRUE(reused.Init(kFrameW, kFrameH, room).ok());
  ASSERT_TRUE(fresh.Init(kFrameW, kFrameH, room).ok());
  BakeMesh bad = room;
  bad.triangles[7] = room.vertex_count();
  EXPECT_EQ(reused.Init(kFrameW, kFrameH, bad).code(), StatusCode::kInvalidArgument);

  std::vector<uint8_t> colours(static_cast<size_t>(room.vertex_count()) * 3);
  std::mt19937 rng(5);
  const CameraView view = ViewFrom({0.5f, 0.5f, 1.6f, 5, 3, 0.8f}, 60);
  reused.SetCamera(view);
  fresh.SetCamera(view);
  for (int draw = 0; draw < 3; ++draw) {
    for (uint8_t& c : colours) c = static_cast<uint8_t>(64 + rng() % 190);
    ASSERT_TRUE(reused.Draw(colours.data(), a.data()).ok());
    ASSERT_TRUE(fresh.Draw(colours.data(), b.data()).ok());
    ASSERT_EQ(a, b) << "draw " << draw;
    EXPECT_EQ(reused.last_drawn_triangles(), fresh.last_drawn_triangles()) << "draw " << draw;
  }
  EXPECT_LT(reused.last_drawn_triangles(), room.triangle_count());  // culled, as the fresh frame
  std::vector<uint32_t> ids_a(static_cast<size_t>(kFrameW) * kFrameH), ids_b(ids_a.size());
  ASSERT_TRUE(reused.DrawTriangleIds(ids_a.data()).ok());
  ASSERT_TRUE(fresh.DrawTriangleIds(ids_b.data()).ok());
  EXPECT_EQ(ids_a, ids_b);

  ASSERT_TRUE(reused.Init(kFrameW / 2, kFrameH, room).ok());
  EXPECT_EQ(reused.width(), kFrameW / 2);
  reused.SetCamera(view);
  EXPECT_TRUE(reused.Draw(colours.data(), a.data()).ok());
}

// --- PNG files

TEST(PngIoTest, RoundTripIsBitExact) {
  constexpr int w = 37, h = 23;  // odd width: rows are not 4-byte aligned
  std::vector<uint8_t> rgb(w * h * 3);
  uint32_t state = 12345;
  for (auto& b : rgb) {
    state = state * 1664525u + 1013904223u;
    b = static_cast<uint8_t>(state >> 24);
  }
  const std::string path = TempPath("roundtrip.png");
  ASSERT_TRUE(WritePngRgb8(path, rgb.data(), w, h).ok());
  EXPECT_FALSE(FileExists(path + ".tmp"));
  std::vector<uint8_t> back;
  int bw = 0, bh = 0;
  const Status st = ReadPngRgb8(path, &back, &bw, &bh);
  ASSERT_TRUE(st.ok()) << st.ToString();
  EXPECT_EQ(bw, w);
  EXPECT_EQ(bh, h);
  EXPECT_EQ(back, rgb);
  std::remove(path.c_str());
}

// A 16-bit RGB PNG (the renderer only writes 8-bit ones). Only trivially
// destructible locals live across setjmp.
bool WriteRgb16Png(const std::string& path, const uint16_t* rgb16, int w, int h) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return false;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_bytep row = static_cast<png_bytep>(std::malloc(static_cast<size_t>(w) * 6));
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::free(row);
    std::fclose(f);
    return false;
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(w), static_cast<png_uint_32>(h), 16, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < h; ++y) {
    for (int i = 0; i < w * 3; ++i) {  // PNG samples are big-endian
      row[i * 2] = static_cast<uint8_t>(rgb16[y * w * 3 + i] >> 8);
      row[i * 2 + 1] = static_cast<uint8_t>(rgb16[y * w * 3 + i] & 0xFF);
    }
    png_write_row(png, row);
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  std::free(row);
  return std::fclose(f) == 0;
}

TEST(PngIoTest, ReadConvertsGrayPaletteRgbaAnd16BitToRgb8) {
  constexpr int w = 3, h = 2;
  // Gray, RGBA, palette (+ tRNS) and 16-bit RGB files written through
  // libpng's simplified API.
  const std::string dir = TempPath("");
  {
    const uint8_t gray[w * h] = {0, 50, 100, 150, 200, 255};
    png_image img{};
    img.version = PNG_IMAGE_VERSION;
    img.width = w;
    img.height = h;
    img.format = PNG_FORMAT_GRAY;
    ASSERT_NE(png_image_write_to_file(&img, (dir + "gray.png").c_str(), 0, gray, 0, nullptr), 0);
    std::vector<uint8_t> rgb;
    int bw = 0, bh = 0;
    ASSERT_TRUE(ReadPngRgb8(dir + "gray.png", &rgb, &bw, &bh).ok());
    ASSERT_EQ(rgb.size(), static_cast<size_t>(w * h * 3));
    for (int i = 0; i < w * h; ++i) {
      for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(rgb[i * 3 + ch], gray[i]);
    }
  }
  {
    uint8_t rgba[w * h * 4];
    for (int i = 0; i < w * h * 4; ++i) rgba[i] = static_cast<uint8_t>(i * 11);
    png_image img{};
    img.version = PNG_IMAGE_VERSION;
    img.width = w;
    img.height = h;
    img.format = PNG_FORMAT_RGBA;
    ASSERT_NE(png_image_write_to_file(&img, (dir + "rgba.png").c_str(), 0, rgba, 0, nullptr), 0);
    std::vector<uint8_t> rgb;
    int bw = 0, bh = 0;
    ASSERT_TRUE(ReadPngRgb8(dir + "rgba.png", &rgb, &bw, &bh).ok());
    ASSERT_EQ(rgb.size(), static_cast<size_t>(w * h * 3));
    // Alpha is dropped, not composited.
    for (int i = 0; i < w * h; ++i) {
      for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(rgb[i * 3 + ch], rgba[i * 4 + ch]);
    }
  }
  {
    const uint8_t colormap[3 * 4] = {10, 20, 30, 200, 100, 0, 0, 0, 255, 7, 8, 9};
    const uint8_t indices[w * h] = {0, 1, 2, 3, 2, 1};
    png_image img{};
    img.version = PNG_IMAGE_VERSION;
    img.width = w;
    img.height = h;
    img.format = PNG_FORMAT_RGB_COLORMAP;
    img.colormap_entries = 4;
    ASSERT_NE(png_image_write_to_file(&img, (dir + "palette.png").c_str(), 0, indices, 0, colormap), 0);
    std::vector<uint8_t> rgb;
    int bw = 0, bh = 0;
    ASSERT_TRUE(ReadPngRgb8(dir + "palette.png", &rgb, &bw, &bh).ok());
    ASSERT_EQ(rgb.size(), static_cast<size_t>(w * h * 3));
    for (int i = 0; i < w * h; ++i) {
      for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(rgb[i * 3 + ch], colormap[indices[i] * 3 + ch]);
    }
  }
  {
    const uint8_t colormap[4 * 2] = {10, 20, 30, 0, 200, 100, 0, 128};  // with tRNS
    const uint8_t indices[w * h] = {0, 1, 1, 0, 0, 1};
    png_image img{};
    img.version = PNG_IMAGE_VERSION;
    img.width = w;
    img.height = h;
    img.format = PNG_FORMAT_RGBA_COLORMAP;
    img.colormap_entries = 2;
    ASSERT_NE(png_image_write_to_file(&img, (dir + "palette_trns.png").c_str(), 0, indices, 0, colormap), 0);
    std::vector<uint8_t> rgb;
    int bw = 0, bh = 0;
    const Status st = ReadPngRgb8(dir + "palette_trns.png", &rgb, &bw, &bh);
    ASSERT_TRUE(st.ok()) << st.ToString();
    ASSERT_EQ(rgb.size(), static_cast<size_t>(w * h * 3));
    for (int i = 0; i < w * h; ++i) {
      for (int ch = 0; ch < 3; ++ch) EXPECT_EQ(rgb[i * 3 + ch], colormap[indices[i] * 4 + ch]);
    }
  }
  {
    // 16-bit RGB through the classic API (the simplified one would tag it linear).
    const std::string path = dir + "rgb16.png";
    uint16_t rgb16[w * h * 3];
    for (int i = 0; i < w * h * 3; ++i) rgb16[i] = static_cast<uint16_t>(i * 3001 + 77);
    ASSERT_TRUE(WriteRgb16Png(path, rgb16, w, h));
    std::vector<uint8_t> rgb;
    int bw = 0, bh = 0;
    ASSERT_TRUE(ReadPngRgb8(path, &rgb, &bw, &bh).ok());
    ASSERT_EQ(rgb.size(), static_cast<size_t>(w * h * 3));
    for (int i = 0; i < w * h * 3; ++i) EXPECT_EQ(rgb[i], rgb16[i] >> 8) << i;  // high byte
  }
  for (const char* name : {"gray.png", "rgba.png", "palette.png", "palette_trns.png", "rgb16.png"}) {
    std::remove((dir + name).c_str());
  }
}

TEST(PngIoTest, MissingNonPngAndTruncatedFilesAreIoErrors) {
  std::vector<uint8_t> rgb;
  int w = 0, h = 0;
  const std::string missing = TempPath("does_not_exist.png");
  Status st = ReadPngRgb8(missing, &rgb, &w, &h);
  EXPECT_EQ(st.code(), StatusCode::kIoError);
  EXPECT_NE(st.message().find(missing), std::string::npos) << st.message();

  const std::string text = TempPath("not_a_png.png");
  std::ofstream(text) << "P3 this is not a PNG file at all\n";
  st = ReadPngRgb8(text, &rgb, &w, &h);
  EXPECT_EQ(st.code(), StatusCode::kIoError);
  EXPECT_NE(st.message().find("not a PNG"), std::string::npos) << st.message();

  // A valid file cut in half: libpng's longjmp path.
  std::vector<uint8_t> img(64 * 64 * 3);
  for (size_t i = 0; i < img.size(); ++i) img[i] = static_cast<uint8_t>(i * 7 + i / 191);
  const std::string whole = TempPath("whole.png");
  ASSERT_TRUE(WritePngRgb8(whole, img.data(), 64, 64).ok());
  std::string bytes;
  {
    std::ifstream in(whole, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  ASSERT_GT(bytes.size(), 100u);
  const std::string cut = TempPath("truncated.png");
  std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  st = ReadPngRgb8(cut, &rgb, &w, &h);
  EXPECT_EQ(st.code(), StatusCode::kIoError);
  EXPECT_NE(st.message().find(cut), std::string::npos) << st.message();

  // A header claiming 30000 x 30000 pixels and no pixel data: refused before allocating.
  {
    std::string header("\x89PNG\r\n\x1a\n", 8);
    const uint8_t ihdr[17] = {'I', 'H', 'D', 'R', 0, 0, 0x75, 0x30, 0, 0, 0x75, 0x30, 8, 2, 0, 0, 0};
    const uint32_t crc = static_cast<uint32_t>(crc32(crc32(0, nullptr, 0), ihdr, sizeof ihdr));
    const uint8_t length[4] = {0, 0, 0, 13};
    const uint8_t crc_be[4] = {static_cast<uint8_t>(crc >> 24), static_cast<uint8_t>(crc >> 16),
                               static_cast<uint8_t>(crc >> 8), static_cast<uint8_t>(crc)};
    header.append(reinterpret_cast<const char*>(length), 4);
    header.append(reinterpret_cast<const char*>(ihdr), sizeof ihdr);
    header.append(reinterpret_cast<const char*>(crc_be), 4);
    // An empty IDAT: libpng reads the header up to the first IDAT.
    const uint8_t idat[12] = {0, 0, 0, 0, 'I', 'D', 'A', 'T', 0x35, 0xaf, 0x06, 0x1e};
    header.append(reinterpret_cast<const char*>(idat), sizeof idat);
    const std::string huge = TempPath("huge.png");
    std::ofstream(huge, std::ios::binary) << header;
    st = ReadPngRgb8(huge, &rgb, &w, &h);
    EXPECT_EQ(st.code(), StatusCode::kIoError);
    EXPECT_NE(st.message().find("too large"), std::string::npos) << st.message();
    std::remove(huge.c_str());
  }

  st = WritePngRgb8("/nonexistent-dir/relight/out.png", img.data(), 64, 64);
  EXPECT_EQ(st.code(), StatusCode::kIoError);
  EXPECT_EQ(WritePngRgb8(whole, img.data(), 0, 64).code(), StatusCode::kInvalidArgument);
  for (const std::string& p : {text, whole, cut}) std::remove(p.c_str());
}

// --- the golden-image comparison utility

TEST(ImageCompareTest, DetectsADifferenceAndWritesActualAndDiffPngs) {
  constexpr int w = 10, h = 6;
  std::vector<uint8_t> expected(w * h * 3);
  for (size_t i = 0; i < expected.size(); ++i) expected[i] = static_cast<uint8_t>(40 + i % 150);
  std::vector<uint8_t> actual = expected;
  actual[(2 * w + 7) * 3 + 1] += 9;  // beyond a 2-level tolerance
  actual[(4 * w + 1) * 3 + 2] += 1;  // within it
  const test_image::Rgb8View ev{expected.data(), w, h};
  const test_image::Rgb8View av{actual.data(), w, h};

  const test_image::DiffStats stats = test_image::DiffRgb8(ev, av, 2);
  EXPECT_EQ(stats.max_channel_diff, 9);
  EXPECT_EQ(stats.bad_pixels, 1);

  const std::string stem = TempPath("compare");
  const ::testing::AssertionResult r = test_image::ImagesMatch(ev, av, test_image::Tolerance{2, 0.0}, stem);
  ASSERT_FALSE(r);
  const std::string msg = r.message();
  EXPECT_NE(msg.find(stem + "_actual.png"), std::string::npos) << msg;
  EXPECT_NE(msg.find(stem + "_diff.png"), std::string::npos) << msg;

  std::vector<uint8_t> back, diff;
  int bw = 0, bh = 0;
  ASSERT_TRUE(ReadPngRgb8(stem + "_actual.png", &back, &bw, &bh).ok());
  EXPECT_EQ(back, actual);
  ASSERT_TRUE(ReadPngRgb8(stem + "_diff.png", &diff, &bw, &bh).ok());
  ASSERT_EQ(diff.size(), actual.size());
  const uint8_t* bad = &diff[(2 * w + 7) * 3];
  EXPECT_EQ(bad[0], 255);  // red: beyond tolerance
  EXPECT_EQ(bad[1], 0);
  const uint8_t* small = &diff[(4 * w + 1) * 3];
  EXPECT_EQ(small[0], 0);  // green: within tolerance but not equal
  EXPECT_GT(small[1], 0);
  const uint8_t* same = &diff[0];
  EXPECT_EQ(same[0], same[1]);  // grey: identical
  EXPECT_LT(same[0], 64);

  // One bad pixel of 60 is within a 2% budget: success, nothing written.
  const std::string stem2 = TempPath("compare_ok");
  EXPECT_TRUE(test_image::ImagesMatch(ev, av, test_image::Tolerance{2, 0.02}, stem2));
  EXPECT_FALSE(FileExists(stem2 + "_actual.png"));
  // Different sizes never match.
  EXPECT_FALSE(test_image::ImagesMatch(ev, test_image::Rgb8View{actual.data(), h, w}, test_image::Tolerance{255, 1.0}, stem2));
  for (const std::string& p : {stem + "_actual.png", stem + "_diff.png", stem2 + "_actual.png"}) {
    std::remove(p.c_str());
  }
}

}  // namespace
}  // namespace relight
