// Radiosity stages (mesher, Embree visibility, form factors, direct light,
// solve, basis, reference, quantisation) against closed forms and against
// each other. Scenes are built in code and kept small so the suite runs in
// seconds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "test_scenes.h"
#include "baker_core.h"
#include "luminaire_basis.h"
#include "quantise.h"
#include "reference.h"
#include "relight/baker/baker.h"
#include "relight/baker/photometry.h"
#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;

// --- scene building ---------------------------------------------------------

using namespace test_scenes;

std::unique_ptr<BakerCore> Core(const Scene& scene, DirectModeKind mode = DirectModeKind::kExact) {
  BakeOptions options;
  options.direct_mode = mode;
  return BuildBakerCore(scene, options, nullptr);
}

// Sum over the patches of input surface `from` to those of `to`, area-weighted:
// the surface-to-surface form factor.
double SurfaceFormFactor(const BakerCore& core, uint32_t from, uint32_t to) {
  double area = 0, sum = 0;
  const auto& patches = core.mesh.patches;
  for (size_t i = 0; i < patches.size(); ++i) {
    if (patches[i].surface != from) continue;
    area += patches[i].area_m2;
    for (size_t j = 0; j < patches.size(); ++j) {
      if (patches[j].surface == to) {
        sum += patches[i].area_m2 *
               core.form_factors(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
      }
    }
  }
  return sum / area;
}

// --- closed forms -------------------------------------------------------------

// Two directly opposed, parallel a x b rectangles at distance c.
double ParallelRectangles(double a, double b, double c) {
  const double x = a / c, y = b / c;
  const double x2 = x * x, y2 = y * y;
  return 2.0 / (kPi * x * y) *
         (std::log(std::sqrt((1 + x2) * (1 + y2) / (1 + x2 + y2))) +
          x * std::sqrt(1 + y2) * std::atan(x / std::sqrt(1 + y2)) +
          y * std::sqrt(1 + x2) * std::atan(y / std::sqrt(1 + x2)) - x * std::atan(x) -
          y * std::atan(y));
}

// Perpendicular rectangles sharing an edge of length l: from the w x l one to the h x l one.
double PerpendicularRectangles(double w, double h, double l) {
  const double W = w / l, H = h / l, W2 = W * W, H2 = H * H, S = std::sqrt(W2 + H2);
  const double log_term =
      std::log((1 + W2) * (1 + H2) / (1 + W2 + H2)) +
      W2 * std::log(W2 * (1 + W2 + H2) / ((1 + W2) * (W2 + H2))) +
      H2 * std::log(H2 * (1 + H2 + W2) / ((1 + H2) * (H2 + W2)));
  return (W * std::atan(1 / W) + H * std::atan(1 / H) - S * std::atan(1 / S) + 0.25 * log_term) /
         (kPi * W);
}

// --- mesh ---------------------------------------------------------------------

TEST(Mesher, QuadGridCountsAndSharedVertices) {
  Scene scene;
  scene.patch_size_m = 0.25;
  scene.surfaces = {Quad("q", {0, 0, 0}, {1, 0, 0}, {1, 0.5, 0}, {0, 0.5, 0})};
  const Mesh mesh = BuildMesh(scene);
  // 1 m x 0.5 m at 0.25 m: 4 x 2 cells, 5 x 3 vertices, 2 triangles per cell.
  EXPECT_EQ(mesh.patch_count(), 8u);
  EXPECT_EQ(mesh.vertex_count(), 15u);
  EXPECT_EQ(mesh.triangles.size(), 3u * 16u);
  EXPECT_EQ(mesh.triangle_surface.size(), 16u);
  double area = 0;
  for (const Patch& p : mesh.patches) {
    EXPECT_EQ(p.corner_count, 4);
    EXPECT_NEAR(p.area_m2, 0.0625, 1e-12);
    EXPECT_NEAR(p.normal[2], 1.0, 1e-12);
    area += p.area_m2;
  }
  EXPECT_NEAR(area, 0.5, 1e-12);
  // Interior vertices are shared by 4 patches, edge ones by 2, corners by 1.
  std::vector<int> histogram(5, 0);
  for (size_t v = 0; v < mesh.vertex_count(); ++v)
    ++histogram[mesh.vertex_patch_offsets[v + 1] - mesh.vertex_patch_offsets[v]];
  EXPECT_EQ(histogram[1], 4);
  EXPECT_EQ(histogram[2], 8);
  EXPECT_EQ(histogram[4], 3);
}

TEST(Mesher, TriangleGridCountsAndWinding) {
  Scene scene;
  scene.patch_size_m = 0.25;
  Surface tri;
  tri.name = "t";
  tri.corners = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  scene.surfaces = {tri};
  const Mesh mesh = BuildMesh(scene);
  // Longest edge sqrt(2) -> k = 6: k^2 sub-triangles, (k+1)(k+2)/2 vertices.
  EXPECT_EQ(mesh.patch_count(), 36u);
  EXPECT_EQ(mesh.vertex_count(), 28u);
  double area = 0;
  for (const Patch& p : mesh.patches) area += p.area_m2;
  EXPECT_NEAR(area, 0.5, 1e-12);
  // Every render triangle CCW from the lit side (+z here).
  for (size_t t = 0; t < mesh.triangles.size(); t += 3) {
    const Vec3& a = mesh.positions[mesh.triangles[t]];
    const Vec3& b = mesh.positions[mesh.triangles[t + 1]];
    const Vec3& c = mesh.positions[mesh.triangles[t + 2]];
    const double cross_z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    EXPECT_GT(cross_z, 0);
  }
  // Interior vertices of a triangular grid are shared by 6 sub-triangles.
  int six = 0;
  for (size_t v = 0; v < mesh.vertex_count(); ++v)
    six += mesh.vertex_patch_offsets[v + 1] - mesh.vertex_patch_offsets[v] == 6;
  EXPECT_EQ(six, 10);  // (k-1)(k-2)/2 interior vertices
}

TEST(Mesher, VerticesAreNotSharedAcrossSurfaces) {
  const Mesh mesh = BuildMesh(ClosedBox(0.5, {0.5, 0.5, 0.5}));
  EXPECT_EQ(mesh.patch_count(), 24u);
  EXPECT_EQ(mesh.vertex_count(), 6u * 9u);  // corners repeated per face
  for (const Patch& p : mesh.patches)
    for (int k = 0; k < p.corner_count; ++k)
      EXPECT_EQ(mesh.vertex_surface[p.vertices[k]], p.surface);
}

TEST(Mesher, PatchSampleWeightsAreExactCellAreas) {
  Scene scene;
  scene.patch_size_m = 10;
  // A trapezoid, so the bilinear Jacobian is not constant.
  const Vec3 c[4] = {{0, 0, 0}, {2, 0, 0}, {1.5, 1, 0}, {0.5, 1, 0}};
  scene.surfaces = {Quad("trap", c[0], c[1], c[2], c[3])};
  const Mesh mesh = BuildMesh(scene);
  ASSERT_EQ(mesh.patch_count(), 1u);
  EXPECT_NEAR(mesh.patches[0].area_m2, 1.5, 1e-12);
  const auto at = [&](double u, double v) {
    Vec3 p;
    for (int a = 0; a < 3; ++a)
      p[a] = (1 - u) * (1 - v) * c[0][a] + u * (1 - v) * c[1][a] + u * v * c[2][a] + (1 - u) * v * c[3][a];
    return p;
  };
  const auto shoelace = [](const Vec3* q) {
    double twice = 0;
    for (int k = 0; k < 4; ++k) twice += q[k][0] * q[(k + 1) % 4][1] - q[(k + 1) % 4][0] * q[k][1];
    return 0.5 * twice;
  };
  double previous_error = 1;
  for (int k : {2, 4, 8}) {
    const std::vector<PatchSample> s = SamplePatch(mesh, mesh.patches[0], k);
    ASSERT_EQ(s.size(), static_cast<size_t>(k * k));
    double centroid_y = 0;
    for (int b = 0; b < k; ++b) {
      for (int a = 0; a < k; ++a) {
        const Vec3 cell[4] = {at(double(a) / k, double(b) / k), at(double(a + 1) / k, double(b) / k),
                              at(double(a + 1) / k, double(b + 1) / k), at(double(a) / k, double(b + 1) / k)};
        EXPECT_NEAR(s[b * k + a].weight, shoelace(cell) / 1.5, 1e-12);
        centroid_y += s[b * k + a].weight * s[b * k + a].point[1];
      }
    }
    // Midpoints are a second-order rule for the centroid: the error falls ~4x per halving.
    const double error = std::abs(centroid_y - mesh.patches[0].centre[1]);
    EXPECT_LT(error, previous_error / 3.5) << "k = " << k;
    previous_error = error;
  }
}

// --- form factors ---------------------------------------------------------------

TEST(FormFactors, PointToPolygonMatchesTheCornerClosedForm) {
  // A 2a x 2a square centred at height h above the point: four corner
  // rectangles, each F = (1/pi) A/sqrt(1+A^2) atan(A/sqrt(1+A^2)), A = a/h.
  const double a = 0.5, h = 1.0;
  const Vec3 poly[4] = {{-a, -a, h}, {-a, a, h}, {a, a, h}, {a, -a, h}};  // faces -z
  const double f = PointToPolygonFormFactor({0, 0, 0}, {0, 0, 1}, poly, 4, {0, 0, -1});
  const double A = a / h;
  const double corner = (A / std::sqrt(1 + A * A) * std::atan(A / std::sqrt(1 + A * A))) / kPi;
  EXPECT_NEAR(f, 4 * corner, 1e-12);
  // Seen from behind: nothing.
  EXPECT_EQ(PointToPolygonFormFactor({0, 0, 2}, {0, 0, -1}, poly, 4, {0, 0, -1}), 0.0);
  // A square straddling the receiver's plane is clipped to its upper half.
  const Vec3 vertical[4] = {{1, -a, -a}, {1, a, -a}, {1, a, a}, {1, -a, a}};  // faces -x
  const Vec3 upper[4] = {{1, -a, 0}, {1, a, 0}, {1, a, a}, {1, -a, a}};
  const double clipped = PointToPolygonFormFactor({0, 0, 0}, {0, 0, 1}, vertical, 4, {-1, 0, 0});
  EXPECT_GT(clipped, 0);
  EXPECT_NEAR(clipped, PointToPolygonFormFactor({0, 0, 0}, {0, 0, 1}, upper, 4, {-1, 0, 0}), 1e-15);
}

TEST(FormFactors, ParallelUnitSquaresMatchTheClosedForm) {
  Scene scene;
  scene.patch_size_m = 0.25;
  scene.surfaces = {
      Quad("bottom", {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}),  // faces +z
      Quad("top", {0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}),     // faces -z
  };
  const auto core = Core(scene);
  const double expected = ParallelRectangles(1, 1, 1);
  EXPECT_NEAR(expected, 0.19982, 1e-5);  // the tabulated value
  const double f01 = SurfaceFormFactor(*core, 0, 1);
  const double f10 = SurfaceFormFactor(*core, 1, 0);
  EXPECT_NEAR(f01, expected, 0.02 * expected);
  EXPECT_NEAR(f10, expected, 0.02 * expected);
  EXPECT_NEAR(f01, f10, 1e-3 * expected);  // equal areas: reciprocity
  RecordProperty("parallel_rel_error", std::to_string(f01 / expected - 1));
}

TEST(FormFactors, PerpendicularSquaresSharingAnEdgeMatchTheClosedForm) {
  Scene scene;
  scene.patch_size_m = 0.25;
  scene.surfaces = {
      Quad("floor", {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}),  // faces +z
      Quad("wall", {0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}),   // x = 0, faces +x
  };
  const auto core = Core(scene);
  const double expected = PerpendicularRectangles(1, 1, 1);
  EXPECT_NEAR(expected, 0.20004, 1e-5);
  const double f01 = SurfaceFormFactor(*core, 0, 1);
  EXPECT_NEAR(f01, expected, 0.02 * expected);
  EXPECT_NEAR(SurfaceFormFactor(*core, 1, 0), expected, 0.02 * expected);
  RecordProperty("perpendicular_rel_error", std::to_string(f01 / expected - 1));
}

TEST(FormFactors, PatchPairsAreReciprocal) {
  // Unequal patch areas (a 1 x 0.6 wall meshed at 0.25 m) and both near and far pairs.
  Scene scene;
  scene.patch_size_m = 0.25;
  scene.surfaces = {
      Quad("floor", {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}),
      Quad("wall", {0, 0, 0}, {0, 1, 0}, {0, 1, 0.6}, {0, 0, 0.6}),
      Quad("top", {0, 0, 1.5}, {0, 1, 1.5}, {1, 1, 1.5}, {1, 0, 1.5}),
  };
  const auto core = Core(scene);
  const auto& p = core->mesh.patches;
  double worst_near = 0, worst_far = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    for (size_t j = i + 1; j < p.size(); ++j) {
      const double aij = p[i].area_m2 * core->form_factors(static_cast<Eigen::Index>(i),
                                                           static_cast<Eigen::Index>(j));
      const double aji = p[j].area_m2 * core->form_factors(static_cast<Eigen::Index>(j),
                                                           static_cast<Eigen::Index>(i));
      if (aij <= 0 && aji <= 0) continue;
      const double rel = std::abs(aij - aji) / std::max(aij, aji);
      (IsNearPair(p[i], p[j]) ? worst_near : worst_far) = std::max(
          IsNearPair(p[i], p[j]) ? worst_near : worst_far, rel);
    }
  }
  // Point sampling on the sender is not exactly reciprocal per pair; these
  // are the measured worst cases with margin (near pairs: 16 points, far: 4).
  EXPECT_LT(worst_near, 0.03);
  EXPECT_LT(worst_far, 0.025);
  RecordProperty("worst_near_reciprocity", std::to_string(worst_near));
  RecordProperty("worst_far_reciprocity", std::to_string(worst_far));
}

// --- closed box ------------------------------------------------------------------

TEST(ClosedBox, FormFactorRowsSumToOne) {
  const auto core = Core(ClosedBox(0.25, {0.5, 0.5, 0.5}));
  ASSERT_EQ(core->mesh.patch_count(), 96u);
  const Eigen::VectorXd rows = core->form_factors.rowwise().sum();
  EXPECT_NEAR(rows.minCoeff(), 1.0, 0.01);
  EXPECT_NEAR(rows.maxCoeff(), 1.0, 0.01);
  RecordProperty("row_sum_max_deviation",
                 std::to_string(std::max(1 - rows.minCoeff(), rows.maxCoeff() - 1)));
  EXPECT_EQ(core->form_factors.diagonal().cwiseAbs().maxCoeff(), 0.0);
}

TEST(ClosedBox, UniformEmissionGivesEOverOneMinusRho) {
  // Different reflectance per channel: three factorisations.
  const Rgb rho{0.3, 0.5, 0.8};
  const auto core = Core(ClosedBox(0.25, rho));
  EXPECT_EQ(core->solver->factorisations(), 3);
  const double e = 10.0;  // lm/m^2 emitted by every patch
  const Eigen::Index n = static_cast<Eigen::Index>(core->mesh.patch_count());
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd m = core->solver->Solve(c, Eigen::VectorXd::Constant(n, e));
    const double expected = e / (1 - rho[c]);
    EXPECT_NEAR(m.minCoeff(), expected, 0.01 * expected) << "channel " << c;
    EXPECT_NEAR(m.maxCoeff(), expected, 0.01 * expected) << "channel " << c;
    // Illuminance form: uniform direct E gives M = rho E / (1 - rho).
    const Eigen::VectorXd m2 = core->solver->SolveExitance(c, Eigen::VectorXd::Constant(n, e));
    EXPECT_NEAR(m2.mean(), rho[c] * e / (1 - rho[c]), 0.01 * rho[c] * e / (1 - rho[c]));
  }
}

TEST(ClosedBox, GreyReflectanceSharesOneFactorisation) {
  const auto core = Core(ClosedBox(0.5, {0.4, 0.4, 0.4}));
  EXPECT_EQ(core->solver->factorisations(), 1);
}

// --- direct light -------------------------------------------------------------------

Scene FloorWithLight(bool blocker) {
  Scene s;
  s.path = "floor.toml";
  s.patch_size_m = 0.5;
  s.surfaces = {Quad("floor", {-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0})};
  if (blocker) {
    s.surfaces.push_back(
        Quad("blocker", {-0.25, -0.25, 1}, {0.25, -0.25, 1}, {0.25, 0.25, 1}, {-0.25, 0.25, 1}));
  }
  Luminaire l;
  l.name = "bulb";
  l.position = {0, 0, 2};
  l.lid.kind = LidKind::kIsotropic;
  l.lid.peak_cd = 1000;
  s.luminaires = {l};
  CalcGrid g;
  g.name = "probe";
  g.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1.5, 0.5, 0}, {0.3, -0.2, 0}, {0.2, 0.2, 0.5}};
  g.normals.assign(g.points.size(), {0, 0, 1});
  s.grids = {g};
  return s;
}

TEST(DirectLight, InverseSquareCosineLaw) {
  const Scene scene = FloorWithLight(false);
  const auto core = Core(scene);
  const LuminaireDirect& d = core->direct[0];
  const Vec3 p = scene.luminaires[0].position;
  const auto check = [&](const Vec3& x, const DirectGeometry& got) {
    const Vec3 r{x[0] - p[0], x[1] - p[1], x[2] - p[2]};
    const double dist = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    const double cos_r = -r[2] / dist;  // receiver normal +z
    const double e_lux = 1000 * got.g_m2;
    EXPECT_NEAR(e_lux, 1000 * cos_r / (dist * dist), 1e-9 * e_lux);  // I cos / d^2
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(got.direction[a], r[a] / dist, 1e-12);
  };
  for (size_t k = 0; k < scene.grids[0].points.size(); ++k)
    check(scene.grids[0].points[k], d.grids[0][k]);
  for (size_t v = 0; v < core->mesh.vertex_count(); ++v)
    check(core->mesh.positions[v], d.vertices[v]);
  // A patch's E is the mean over its area: for a far patch it is close to the
  // value at its centre (1/d^3 varies by a few percent across 0.5 m at ~2.9 m).
  const Eigen::VectorXd e = PatchIlluminance(d, [](const Vec3&) { return 1000.0; });
  for (size_t i = 0; i < core->mesh.patch_count(); ++i) {
    const Vec3& c = core->mesh.patches[i].centre;
    const double dist = std::sqrt(c[0] * c[0] + c[1] * c[1] + 4);
    EXPECT_NEAR(e(static_cast<Eigen::Index>(i)), 1000 * 2 / (dist * dist * dist),
                0.03 * 1000 * 2 / (dist * dist * dist));
  }
}

TEST(DirectLight, PatchNextToTheLuminaireGetsItsExactFlux) {
  // An isotropic source 5 cm above the centre of a 0.5 m patch: the patch's
  // mean illuminance is I * solid angle / area, far from I / h^2 at the centre.
  Scene scene;
  scene.path = "near.toml";
  scene.patch_size_m = 0.5;
  scene.surfaces = {Quad("floor", {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0})};
  Luminaire l;
  l.position = {0.25, 0.25, 0.05};
  scene.luminaires = {l};
  const auto core = Core(scene);
  const Eigen::VectorXd e = PatchIlluminance(core->direct[0], [](const Vec3&) { return 1000.0; });
  const double a = 0.25, h = 0.05;
  const double omega = 4 * std::atan(a * a / (h * std::sqrt(2 * a * a + h * h)));
  EXPECT_NEAR(e(0), 1000 * omega / 0.25, 1e-9 * e(0));
  // And the whole floor receives I times its solid angle (four corner rectangles).
  const auto corner = [h](double x, double y) {
    return std::atan(x * y / (h * std::sqrt(x * x + y * y + h * h)));
  };
  const double omega_floor =
      corner(0.25, 0.25) + corner(0.75, 0.25) + corner(0.25, 0.75) + corner(0.75, 0.75);
  EXPECT_NEAR(e.sum() * 0.25, 1000 * omega_floor, 1e-9 * 1000 * omega_floor);
}

TEST(DirectLight, BlockerCastsAShadow) {
  const Scene scene = FloorWithLight(true);
  const auto core = Core(scene);
  const LuminaireDirect& d = core->direct[0];
  // The 0.5 m blocker halfway down throws a 1 m shadow square on the floor.
  const auto& grid = d.grids[0];
  EXPECT_EQ(grid[0].g_m2, 0.0);  // (0, 0): under the blocker
  EXPECT_EQ(grid[4].g_m2, 0.0);  // (0.3, -0.2): inside the shadow
  EXPECT_EQ(grid[5].g_m2, 0.0);  // (0.2, 0.2, 0.5): above the floor, still shadowed
  EXPECT_GT(grid[1].g_m2, 0.0);  // (1, 0): lit
  EXPECT_NEAR(grid[1].g_m2, 2 / std::pow(5.0, 1.5), 1e-12);
  for (size_t v = 0; v < core->mesh.vertex_count(); ++v) {
    const Vec3& x = core->mesh.positions[v];
    if (x[2] != 0) continue;  // floor vertices only
    const bool shadowed = std::abs(x[0]) < 0.5 - 1e-6 && std::abs(x[1]) < 0.5 - 1e-6;
    const bool lit = std::abs(x[0]) > 0.5 + 1e-6 || std::abs(x[1]) > 0.5 + 1e-6;
    if (shadowed) {
      EXPECT_EQ(d.vertices[v].g_m2, 0.0) << x[0] << "," << x[1];
    }
    if (lit) {
      EXPECT_GT(d.vertices[v].g_m2, 0.0) << x[0] << "," << x[1];
    }
  }
}

TEST(DirectLight, FlushMountedLuminaireLightsEveryFloorVertexUpToTheCorners) {
  // A luminaire exactly on the ceiling plane must not shadow itself, and
  // floor vertices on the walls' edges must not be shadowed by the walls.
  Scene scene = ClosedBox(0.25, {0.5, 0.5, 0.5});
  Luminaire l;
  l.position = {0.5, 0.5, 1.0};
  scene.luminaires = {l};
  const auto core = Core(scene);
  int floor_vertices = 0;
  for (size_t v = 0; v < core->mesh.vertex_count(); ++v) {
    if (core->mesh.vertex_surface[v] != 0) continue;  // the floor
    ++floor_vertices;
    const Vec3& x = core->mesh.positions[v];
    const double dx = x[0] - 0.5, dy = x[1] - 0.5, d2 = dx * dx + dy * dy + 1;
    EXPECT_NEAR(core->direct[0].vertices[v].g_m2, 1 / (d2 * std::sqrt(d2)), 1e-12)
        << x[0] << "," << x[1];
  }
  EXPECT_EQ(floor_vertices, 25);
}

// --- linearity: basis vs reference ----------------------------------------------------

// 100 (1 + cos g + cos^2 g) cd = sum_l w_l P_l(cos g) with
// w = 100 {4/3, 1, 2/3, 0}: exact at degree 2 (and 3).
double PolynomialBeam(double gamma_deg) {
  const double c = std::cos(gamma_deg * kPi / 180);
  return 100 * (1 + c + c * c);
}
const std::vector<double> kBeamLegendre = {100 * 4.0 / 3.0, 100, 100 * 2.0 / 3.0, 0};

// A room with a table, coloured walls and a grid; the beam as a fine table
// (0.01 degree steps: linear interpolation within ~1e-8 of the polynomial).
Scene Room() {
  Scene s;
  s.name = "room";
  s.path = "room.toml";
  s.patch_size_m = 0.5;
  s.surfaces = InwardBox({0, 0, 0}, {3, 2.5, 2.4}, {0.3, 0.25, 0.2}, {0.7, 0.6, 0.5},
                         {0.8, 0.8, 0.8});
  // A table top (lit from above) that shadows part of the floor.
  s.surfaces.push_back(Quad("table", {1, 1, 0.7}, {2, 1, 0.7}, {2, 1.6, 0.7}, {1, 1.6, 0.7},
                            {0.4, 0.3, 0.2}));
  s.surfaces.push_back(Quad("table under", {1, 1, 0.69}, {1, 1.6, 0.69}, {2, 1.6, 0.69},
                            {2, 1, 0.69}, {0.4, 0.3, 0.2}));
  Luminaire l;
  l.name = "spot";
  l.position = {1.2, 1.1, 2.2};
  l.sh_degree = 3;
  l.use_sigma = false;
  l.lid.kind = LidKind::kTable;
  for (int k = 0; k <= 18000; ++k) {
    l.lid.gamma_deg.push_back(k * 0.01);
    l.lid.candela.push_back(PolynomialBeam(k * 0.01));
  }
  s.luminaires = {l};
  CalcGrid g = WorkplaneGrid();
  g.columns = 5;
  g.rows = 4;
  s.grids = {g};
  return s;
}

double MaxRelativeError(const std::vector<Rgb>& got, const std::vector<Rgb>& want) {
  double peak = 0, worst = 0;
  for (size_t k = 0; k < want.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      peak = std::max(peak, std::abs(want[k][c]));
      worst = std::max(worst, std::abs(got[k][c] - want[k][c]));
    }
  return worst / peak;
}

// Recombines a float64 receiver basis at `setting` (Dobashi Eq. 18), plus
// the exact direct term when the basis carries one.
std::vector<Rgb> Recombine(const ReceiverBasis& set, const Luminaire& lum,
                           const FixtureSetting& setting, const std::vector<Rgb>* rho_over_pi) {
  const Vec3 axis = BeamAxis(lum.mounting, setting.pan_deg, setting.tilt_deg);
  const std::vector<double> w = TermWeights(kBeamLegendre, axis, false);
  std::vector<Rgb> out(static_cast<size_t>(set.basis[0].rows()), Rgb{0, 0, 0});
  for (size_t r = 0; r < out.size(); ++r) {
    for (int c = 0; c < 3; ++c) {
      double v = 0;
      for (size_t t = 0; t < w.size(); ++t)
        v += w[t] * set.basis[c](static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(t));
      if (!set.direct.empty()) {
        const double e = set.direct[r].g_m2 * ExactIntensity(lum.lid, axis, set.direct[r].direction);
        v += rho_over_pi ? (*rho_over_pi)[r][c] * e : e;
      }
      out[r][c] = v * setting.dimmer * setting.colour[c];
    }
  }
  return out;
}

class Linearity : public ::testing::TestWithParam<DirectModeKind> {};

TEST_P(Linearity, RecombinedBasisEqualsTheReferenceAtTwoAims) {
  const DirectModeKind mode = GetParam();
  const Scene scene = Room();
  const auto core = Core(scene, mode);
  const LuminaireBasis basis = ComputeLuminaireBasis(*core, 0, mode);
  ASSERT_EQ(basis.sets.size(), 2u);
  ASSERT_EQ(basis.sets[0].basis[0].cols(), ShTermCount(3));
  EXPECT_EQ(basis.sets[0].direct.empty(), mode == DirectModeKind::kAllInSh);
  std::vector<Rgb> rho_over_pi;
  for (const Rgb& r : core->mesh.vertex_reflectance) rho_over_pi.push_back({r[0] / kPi, r[1] / kPi, r[2] / kPi});

  BakeOptions options;
  options.direct_mode = mode;
  Baker baker(scene, options);
  for (const FixtureSetting& setting : {FixtureSetting{0, 0, 1, {1, 1, 1}},
                                        FixtureSetting{40, 35, 0.8, {1, 0.5, 0.25}}}) {
    const ReferenceResult ref = baker.Reference({setting});
    const std::vector<Rgb> vertices =
        Recombine(basis.sets[0], scene.luminaires[0], setting, &rho_over_pi);
    const std::vector<Rgb> grid = Recombine(basis.sets[1], scene.luminaires[0], setting, nullptr);
    const bool exact = mode == DirectModeKind::kExact;
    const double vertex_err = MaxRelativeError(
        vertices, exact ? ref.vertex_luminance : ref.vertex_luminance_patch_average);
    const double grid_err = MaxRelativeError(grid, ref.grid_illuminance[0]);
    EXPECT_LT(vertex_err, 1e-6) << "pan " << setting.pan_deg;
    EXPECT_LT(grid_err, 1e-6) << "pan " << setting.pan_deg;
    RecordProperty("vertex_rel_error_pan" + std::to_string(int(setting.pan_deg)),
                   std::to_string(vertex_err));
    RecordProperty("grid_rel_error_pan" + std::to_string(int(setting.pan_deg)),
                   std::to_string(grid_err));
    // The reference is not trivially zero and the table shadows the floor.
    EXPECT_GT(ref.vertex_luminance[0][0] + ref.vertex_luminance.back()[0], 0.0);
    double direct_max = 0;
    for (const Rgb& e : ref.grid_direct_illuminance[0]) direct_max = std::max(direct_max, e[1]);
    EXPECT_GT(direct_max, 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(BothModes, Linearity,
                         ::testing::Values(DirectModeKind::kExact, DirectModeKind::kAllInSh));

TEST(Reference, DimmerAndColourScaleLinearly) {
  const Scene scene = Room();
  Baker baker(scene, BakeOptions{});
  const ReferenceResult full = baker.Reference({FixtureSetting{10, 20, 1, {1, 1, 1}}});
  const ReferenceResult dim = baker.Reference({FixtureSetting{10, 20, 0.5, {0.2, 1, 0.6}}});
  const double level[3] = {0.1, 0.5, 0.3};
  for (size_t v = 0; v < full.vertex_luminance.size(); ++v)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(dim.vertex_luminance[v][c], level[c] * full.vertex_luminance[v][c],
                  1e-12 * (1 + full.vertex_luminance[v][c]));
  EXPECT_THROW(baker.Reference({}), std::invalid_argument);
}

// --- quantisation -------------------------------------------------------------------------

TEST(Quantise, ScaleRepresentsTheStepExactly) {
  for (double step : {1e-9, 0.37, 1.0, 3.0, 12345.678}) {
    const QuantScale s = MakeQuantScale(step);
    EXPECT_GE(s.mantissa, 1 << 29);
    EXPECT_LT(s.mantissa, 1 << 30);
    // Rounded up, so a block's largest value never exceeds the top code.
    EXPECT_GE(QuantScaleValue(s), step);
    EXPECT_LT(QuantScaleValue(s) - step, step * std::ldexp(1.0, -29));
  }
  const QuantScale zero = MakeQuantScale(0);
  EXPECT_EQ(zero.mantissa, 0);
  EXPECT_EQ(QuantScaleValue(zero), 0.0);
}

TEST(Quantise, Int16RoundTripWithinHalfAStep) {
  std::mt19937 rng(7);
  for (double magnitude : {1e-6, 0.02, 1.0, 850.0}) {
    std::uniform_real_distribution<double> dist(-magnitude, magnitude);
    std::vector<double> x(101);
    for (double& v : x) v = dist(rng);
    x[17] = -1.3 * magnitude;  // the largest magnitude is negative
    std::vector<int16_t> q(2 * x.size(), 99);
    const QuantScale s = QuantiseInt16(x.data(), x.size(), 1, q.data() + 1, 2);
    const double step = QuantScaleValue(s);
    EXPECT_EQ(q[2 * 17 + 1], -32767);
    for (size_t k = 0; k < x.size(); ++k) {
      EXPECT_EQ(q[2 * k], 99);  // the stride leaves other slots alone
      EXPECT_LE(std::abs(q[2 * k + 1] * step - x[k]), 0.5 * step * (1 + 1e-9));
    }
  }
  std::vector<double> zeros(5, 0.0);
  std::vector<int16_t> q(5, 1);
  const QuantScale s = QuantiseInt16(zeros.data(), 5, 1, q.data(), 1);
  EXPECT_EQ(s.mantissa, 0);
  for (int16_t v : q) EXPECT_EQ(v, 0);
}

TEST(Quantise, Uint32RoundTripWithinHalfAStep) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> dist(0, 3.7);
  std::vector<double> g(64);
  for (double& v : g) v = dist(rng);
  g[3] = 0;
  std::vector<uint32_t> q(g.size());
  const QuantScale s = QuantiseUint32(g.data(), g.size(), q.data());
  const double step = QuantScaleValue(s);
  // The largest value lands within 2^-29 (relative) of the top code.
  EXPECT_GE(*std::max_element(q.begin(), q.end()), 4294967295u - 8u);
  EXPECT_EQ(q[3], 0u);
  for (size_t k = 0; k < g.size(); ++k) EXPECT_LE(std::abs(q[k] * step - g[k]), 0.5 * step * (1 + 1e-9));
}

TEST(Quantise, FixedFormatsRoundAndSaturate) {
  EXPECT_EQ(ToQ16_16(1.5).raw(), 98304);
  EXPECT_EQ(ToQ16_16(-1.0 / 65536 / 3).raw(), 0);
  EXPECT_EQ(ToQ16_16(-2.0 / 65536 / 3).raw(), -1);
  EXPECT_EQ(ToQ16_16(1e9).raw(), INT32_MAX);
  EXPECT_EQ(ToQ1_14(1.0).raw(), 16384);
  EXPECT_EQ(ToQ1_14(-1.0).raw(), -16384);
  EXPECT_EQ(ToLevelQ1_15(1.0).raw(), 32767);
  EXPECT_EQ(ToLevelQ1_15(0.5).raw(), 16384);
  EXPECT_EQ(ToLevelQ1_15(-3).raw(), 0);
  EXPECT_EQ(ToQ48_16(1000.25).raw(), 1000 * 65536 + 16384);
  EXPECT_EQ(ToAlbedo(1.0), 65535);
  EXPECT_EQ(ToAlbedo(0.5), 32768);
}

// --- the assembled bake -----------------------------------------------------------------------

TEST(Bake, QuantisedBasisMatchesTheFloat64BasisWithinHalfAStep) {
  const Scene scene = Room();
  BakeOptions options;
  options.lid_samples = 360;
  Baker baker(scene, options);
  const relight::Bake bake = baker.Bake();
  const auto core = Core(scene, DirectModeKind::kExact);
  const LuminaireBasis basis = ComputeLuminaireBasis(*core, 0, DirectModeKind::kExact);

  ASSERT_EQ(bake.luminaires.size(), 1u);
  const BakeLuminaire& lum = bake.luminaires[0];
  EXPECT_EQ(lum.sh_degree, 3);
  EXPECT_EQ(lum.use_sigma, 0);
  EXPECT_EQ(lum.direct_mode, DirectMode::kExactDirect);
  EXPECT_EQ(lum.lid.candela.size(), 361u);
  EXPECT_NEAR(static_cast<double>(lum.lid.candela[0]) / 65536.0, 300.0, 1e-4);
  EXPECT_EQ(bake.mesh.vertex_count(), core->mesh.vertex_count());
  EXPECT_EQ(bake.mesh.triangle_count(), core->mesh.triangles.size() / 3);
  EXPECT_EQ(bake.mesh.surface_names.size(), scene.surfaces.size());
  ASSERT_EQ(lum.receivers.size(), bake.receiver_set_count());
  for (uint32_t set = 0; set < bake.receiver_set_count(); ++set) {
    const BakeLightReceivers& rx = lum.receivers[set];
    const ReceiverBasis& want = basis.sets[set];
    const uint32_t count = bake.receiver_count(set);
    ASSERT_EQ(rx.basis.size(), static_cast<size_t>(ShTermCount(3)) * count * 3);
    for (int t = 0; t < ShTermCount(3); ++t) {
      for (int c = 0; c < 3; ++c) {
        const double step = QuantScaleValue(rx.basis_scale[t * 3 + c]);
        for (uint32_t r = 0; r < count; ++r) {
          const double got = rx.basis[(static_cast<size_t>(t) * count + r) * 3 + c] * step;
          ASSERT_LE(std::abs(got - want.basis[c](r, t)), 0.5 * step * (1 + 1e-9) + 1e-300)
              << "set " << set << " term " << t << " receiver " << r << " channel " << c;
        }
      }
    }
    ASSERT_EQ(rx.geometry.size(), count);
    const double gstep = QuantScaleValue(rx.geometry_scale);
    for (uint32_t r = 0; r < count; ++r) {
      EXPECT_LE(std::abs(rx.geometry[r] * gstep - want.direct[r].g_m2), 0.5 * gstep * (1 + 1e-9));
      for (int a = 0; a < 3; ++a)
        EXPECT_NEAR(rx.direction[3 * r + a] / 16384.0, want.direct[r].direction[a], 0.5 / 16384);
    }
  }
  // Automatic white: positive and no brighter than the brightest vertex.
  EXPECT_GT(bake.white_luminance, 0);
  const BakeReport& report = baker.report();
  EXPECT_EQ(report.patches, core->mesh.patch_count());
  EXPECT_EQ(report.sh_terms, 16u);
  EXPECT_EQ(report.grid_points, 20u);
}

TEST(Bake, BadInputIsASceneError) {
  Scene scene = ClosedBox(0.5, {0.5, 0.5, 0.5});
  scene.surfaces[0].reflectance = {1.2, 0.5, 0.5};
  EXPECT_THROW(Baker(scene, BakeOptions{}), SceneError);
  scene = ClosedBox(0.5, {0.5, 0.5, 0.5});
  scene.patch_size_m = 0;
  EXPECT_THROW(Baker(scene, BakeOptions{}), SceneError);
  scene = ClosedBox(0.5, {0.5, 0.5, 0.5});
  scene.luminaires.push_back(Luminaire{});
  scene.luminaires[0].sh_degree = kMaxShDegree + 1;
  scene.luminaires[0].line = 12;
  try {
    Baker baker(scene, BakeOptions{});
    ADD_FAILURE() << "no error";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.line(), 12);
    EXPECT_NE(std::string(e.what()).find("sh_degree"), std::string::npos);
  }
}

}  // namespace
}  // namespace relight::baker
