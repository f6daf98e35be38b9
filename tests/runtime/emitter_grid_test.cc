// Run-time emitters on the calculation grids (issue 15 item 4): the engine's
// grid illuminance from an emitter, gathered in fixed point over the bake's
// node-to-point links (GLNK), against a float64 reference: the baker's own
// hierarchical solve of the same emission (every leaf's exitance), gathered
// at each grid point over *every* leaf with the dense point-to-patch factors
// and visibility (BakerCore::gather). Bars: 2 % of peak max, 0.2 % mean.
// Also: the links round-trip through a file, the engine allocates nothing
// placing, dimming and removing an emitter with grids, and removal restores
// the grids bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "baker_core.h"
#include "count_allocations.h"
#include "emitter_grids.h"
#include "surface_emitter_coverage.h"
#include "surface_emitter_solve.h"
#include "relight/baker/baker.h"
#include "relight/engine/engine.h"
#include "surface_emitter_test_support.h"

namespace relight::testing {
namespace {

constexpr double kPi = 3.14159265358979323846;

baker::BakeOptions Hierarchical() {
  baker::BakeOptions options;
  options.solver = baker::SolverKind::kHierarchical;
  options.solve_tolerance = 1e-9;  // the reference, converged well past the runtime's
  return options;
}

LightQ12 Light(double cd_m2) { return LightQ12::FromRaw(static_cast<int32_t>(std::lround(cd_m2 * 4096))); }

void DarkenLuminaires(Engine* engine) {
  for (int i = 0; i < engine->luminaire_count(); ++i)
    ASSERT_TRUE(engine->SetDimmer(i, Q1_15::FromRaw(0)).ok());
}

struct Emitter {
  std::string surface;
  std::vector<Vec3> corners;
  Vec3 normal;
};

// The Cornell box (its floor grid, 10 x 10 points, some under the blocks):
// a quadrilateral across ceiling nodes, off the patch grid's lines, and a
// window on the back wall.
const Emitter kCeiling{"ceiling",
                       {{0.203, -0.221, 0.5488}, {0.361, -0.197, 0.5488}, {0.347, -0.362, 0.5488}, {0.212, -0.338, 0.5488}},
                       {0, 0, -1}};
const Emitter kWindow{"back_wall",
                      {{0.08, -0.5592, 0.12}, {0.47, -0.5592, 0.12}, {0.47, -0.5592, 0.42}, {0.08, -0.5592, 0.42}},
                      {0, 1, 0}};

// Per patch, the fraction the emitter covers (float64 clip in the plane).
Eigen::VectorXd CoveredFraction(const baker::Scene& scene, const baker::Mesh& mesh, const Emitter& em) {
  const AxisPlane plane(em.normal);
  const std::vector<Vec2> clip = plane.Polygon(em.corners);
  uint32_t surface = 0;
  while (scene.surfaces[surface].name != em.surface) ++surface;
  Eigen::VectorXd fraction = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.patch_count()));
  for (size_t i = 0; i < mesh.patch_count(); ++i) {
    const baker::Patch& p = mesh.patches[i];
    if (p.surface != surface) continue;
    std::vector<Vec3> corners;
    for (int k = 0; k < p.corner_count; ++k) corners.push_back(mesh.positions[p.vertices[k]]);
    const std::vector<Vec2> patch = plane.Polygon(corners);
    const std::vector<Vec2> cut = ClipConvex(patch, clip);
    if (cut.size() >= 3) fraction(static_cast<Eigen::Index>(i)) = SignedArea(cut) / SignedArea(patch);
  }
  return fraction;
}

struct GridError {
  double max = 0, mean = 0;  // of peak, worst channel
  int quick = 0;             // quick answers in the compared Update (a move's)
};

// The engine's grid 0 with the emitter alone (luminaires dark), against the reference.
// The reference spreads the emission evenly over each patch by its covered
// fraction, as fractional emissivity does, so FE is what it measures by
// default; adaptive refine is compared too where a test says so.
GridError CompareGrid(const baker::Scene& scene, const Emitter& em, const double luminance[3],
                      const baker::BakeOptions& bake_options = Hierarchical(),
                      SurfaceEmitterMethod method = SurfaceEmitterMethod::kFractionalEmissivity,
                      double moved_from_dx_m = 0, bool quick_changes = true) {
  baker::Baker baker(scene, bake_options);
  Engine engine;
  EngineOptions options;
  options.emitter_quick_changes = quick_changes;
  EXPECT_TRUE(engine.Open(baker.Bake(), options).ok());
  EXPECT_TRUE(engine.bake().hierarchy && engine.bake().hierarchy->has_grid_links());
  DarkenLuminaires(&engine);
  const LightQ12 light[3] = {Light(luminance[0]), Light(luminance[1]), Light(luminance[2])};
  SurfaceEmitterShape shape = MakeShape(em.surface, em.corners);
  shape.method = method;
  if (moved_from_dx_m != 0) {  // a move's answer: placed there first, settled, then moved here
    std::vector<Vec3> from = em.corners;
    for (Vec3& c : from) c[0] += moved_from_dx_m;
    SurfaceEmitterShape start = MakeShape(em.surface, from);
    start.method = method;
    EXPECT_TRUE(engine.SetSurfaceEmitter(0, start, light).ok());
    UpdateSettled(&engine);
  }
  EXPECT_TRUE(engine.SetSurfaceEmitter(0, shape, light).ok());
  engine.Update();
  const int quick = engine.last_update_emitters_quick();
  const int32_t* got = engine.grid_illuminance(0).raw();
  const uint32_t points = engine.bake().grids[0].point_count();

  const auto core = baker::BuildBakerCore(scene, Hierarchical(), nullptr);
  const Eigen::VectorXd fraction = CoveredFraction(scene, core->mesh, em);
  EXPECT_GT(fraction.sum(), 1.0);
  GridError worst;
  worst.quick = quick;
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd exitance = core->hierarchical_solver->Solve(c, kPi * luminance[c] * fraction);
    const Eigen::VectorXd want = core->gather[0] * exitance;  // lux, every leaf
    const double peak = want.maxCoeff();
    double max_error = 0, sum_error = 0, signed_sum = 0;
    for (uint32_t p = 0; p < points; ++p) {
      signed_sum += got[3 * p + c] / 4096.0 - want(p);
      const double e = std::abs(got[3 * p + c] / 4096.0 - want(p));
      max_error = std::max(max_error, e);
      sum_error += e;
    }
    const double mean_error = sum_error / points;
    std::printf("[ measured ] signed mean %.4f %% of peak\n", 100 * signed_sum / points / peak);
    std::printf("[ measured ] %s, channel %d: grid peak %.2f lux, max error %.3f %% of peak, "
                "mean %.4f %% of peak\n",
                em.surface.c_str(), c, peak, 100 * max_error / peak, 100 * mean_error / peak);
    worst.max = std::max(worst.max, max_error / peak);
    worst.mean = std::max(worst.mean, mean_error / peak);
  }
  const BakeHierarchy& h = *engine.bake().hierarchy;
  std::printf("[ measured ] %u grid points, %zu grid links (%.1f per point) over %u nodes\n", points,
              h.grid_link_node.size(), static_cast<double>(h.grid_link_node.size()) / points,
              h.node_count());
  return worst;
}

baker::Scene Cornell() {
  baker::Scene s = baker::LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/cornell_box.toml");
  return s;
}

TEST(EmitterGrid, CeilingPanelMatchesTheFloat64Gather) {
  const double luminance[3] = {200, 120, 45};  // cd/m^2, a warm white
  const GridError e = CompareGrid(Cornell(), kCeiling, luminance);
  EXPECT_LE(e.max, 0.02);
  EXPECT_LE(e.mean, 0.002);
  RecordProperty("grid_max_error_over_peak", std::to_string(e.max));
  RecordProperty("grid_mean_error_over_peak", std::to_string(e.mean));
  // Adaptive refine against the same reference (which spreads the emission
  // over each patch as FE does): measured 0.36 % max, 0.14 % mean.
  const GridError ar = CompareGrid(Cornell(), kCeiling, luminance, Hierarchical(),
                                   SurfaceEmitterMethod::kAdaptiveRefine);
  EXPECT_LE(ar.max, 0.02);
  EXPECT_LE(ar.mean, 0.002);
}

// Adaptive-refine moves against the same float64 gather, to the same bars:
// 3 mm, within quick reach (1/32 of the table's source side, 3.7 mm here),
// answered without a sweep (EngineOptions::emitter_quick_changes); 5 cm,
// beyond it, solved at once (a quick answer would be 0.30 % of peak mean
// off there, measured).
TEST(EmitterGrid, MovesOfTheCeilingPanelMatchTheFloat64GatherQuickOrNot) {
  const double luminance[3] = {200, 120, 45};
  const GridError near = CompareGrid(Cornell(), kCeiling, luminance, Hierarchical(),
                                     SurfaceEmitterMethod::kAdaptiveRefine, -0.003);
  EXPECT_EQ(near.quick, 1);
  EXPECT_LE(near.max, 0.02);
  EXPECT_LE(near.mean, 0.002);
  const GridError far = CompareGrid(Cornell(), kCeiling, luminance, Hierarchical(),
                                    SurfaceEmitterMethod::kAdaptiveRefine, -0.05);
  EXPECT_EQ(far.quick, 0);
  EXPECT_LE(far.max, 0.02);
  EXPECT_LE(far.mean, 0.002);
}

TEST(EmitterGrid, WallWindowMatchesTheFloat64Gather) {
  const double luminance[3] = {1000, 1000, 1100};  // a bright, cool window
  const GridError e = CompareGrid(Cornell(), kWindow, luminance);
  EXPECT_LE(e.max, 0.02);
  // Measured 0.0128 % mean (0.095 % max) with the source-moment term in the
  // engine's solve (surface_emitter_moments.h); 0.33 % without it, a dark
  // bias of the interreflected light.
  EXPECT_LE(e.mean, 0.002);
}

// The grid step alone: the engine's own fixed-point exitance of the window,
// gathered over the GLNK links in fixed point (EmitterGrids) against the same
// exitance gathered in float64 over every leaf with the dense factors. What
// this measures is the links' level choice (BakeOptions::grid_link_epsilon)
// and the fixed point of the gather, without the solve's own error.
TEST(EmitterGrid, LinksGatherTheSolvedExitanceLikeEveryLeaf) {
  const baker::Scene scene = Cornell();
  const Bake bake = baker::Baker(scene, Hierarchical()).Bake();
  const auto core = baker::BuildBakerCore(scene, Hierarchical(), nullptr);
  const BakeHierarchy& h = *bake.hierarchy;
  HierarchySolveQ32 solver;
  ASSERT_TRUE(solver.Init(bake).ok());
  std::vector<int64_t> coverage(h.node_count(), 0), exitance(3 * size_t{h.node_count()}, 0);
  const SurfaceEmitterShape shape = MakeShape(kWindow.surface, kWindow.corners);
  ASSERT_TRUE(SurfaceEmitterCoverageQ32(h, bake.mesh, SurfaceRoot(bake, kWindow.surface), shape.corners_q16,
                                        shape.corner_count, coverage.data())
                  .ok());
  solver.SolveRgb(coverage.data(), nullptr, exitance.data(), nullptr);
  EmitterGrids grids;
  grids.Open(bake);
  ASSERT_TRUE(grids.active());
  grids.OnSolved(0, exitance.data());
  const int32_t* got = grids.unit_q24(0);
  const baker::Hierarchy& tree = core->hierarchical_solver->hierarchy();
  const Eigen::MatrixXd& g = core->gather[0];
  double worst_max = 0, worst_mean = 0;
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd leaf_exitance(g.cols());
    for (uint32_t k = 0; k < tree.nodes.size(); ++k) {
      if (tree.nodes[k].leaf()) leaf_exitance(tree.nodes[k].patch) = std::ldexp(exitance[3 * k + c], -32);
    }
    const Eigen::VectorXd want = kPi * (g * leaf_exitance);  // lux per cd/m^2
    const double peak = want.maxCoeff();
    double max_error = 0, sum_error = 0;
    for (Eigen::Index p = 0; p < want.size(); ++p) {
      const double e = std::abs(std::ldexp(got[3 * p + c], -24) - want(p));
      max_error = std::max(max_error, e);
      sum_error += e;
    }
    worst_max = std::max(worst_max, max_error / peak);
    worst_mean = std::max(worst_mean, sum_error / static_cast<double>(want.size()) / peak);
  }
  std::printf("[ measured ] links vs every leaf, same exitance: max %.4f %%, mean %.5f %% of peak\n",
              100 * worst_max, 100 * worst_mean);
  EXPECT_LE(worst_max, 0.02);
  EXPECT_LE(worst_mean, 0.002);
}

// The figure in docs/hierarchy.md "Grids": the 16k-patch living room (its
// floor grid, 12 x 9 points) under a 1 m^2 ceiling panel of 3000 cd/m^2.
// About 2 minutes and 1 GB, so disabled; run it with
//   emitter_grid_test --gtest_also_run_disabled_tests --gtest_filter='*LivingRoom*'
TEST(EmitterGrid, DISABLED_LivingRoom16kCeilingPanel) {
  baker::Scene scene = baker::LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/living_room.toml");
  scene.patch_size_m = 0.092;
  const Emitter panel{"room/+z", {{2.5, 1.5, 2.7}, {3.5, 1.5, 2.7}, {3.5, 2.5, 2.7}, {2.5, 2.5, 2.7}}, {0, 0, -1}};
  const double luminance[3] = {3000, 3000, 3000};
  baker::BakeOptions bake_options;  // the engine's bake as relight-bake makes it
  bake_options.solver = baker::SolverKind::kHierarchical;
  const GridError e = CompareGrid(scene, panel, luminance, bake_options);
  EXPECT_LE(e.max, 0.02);
  EXPECT_LE(e.mean, 0.002);
}

// The same panel by adaptive refine moved 10 cm there, solved at once and
// answered quickly. About 5 minutes, so disabled.
TEST(EmitterGrid, DISABLED_LivingRoom16kCeilingPanelMoved) {
  baker::Scene scene = baker::LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/living_room.toml");
  scene.patch_size_m = 0.092;
  const Emitter panel{"room/+z", {{2.5, 1.5, 2.7}, {3.5, 1.5, 2.7}, {3.5, 2.5, 2.7}, {2.5, 2.5, 2.7}}, {0, 0, -1}};
  const double luminance[3] = {3000, 3000, 3000};
  baker::BakeOptions bake_options;
  bake_options.solver = baker::SolverKind::kHierarchical;
  const double moves[2] = {-0.1, -0.03};  // beyond quick reach (3.2 cm here) and within it
  for (const double dx : moves) {
    const GridError moved = CompareGrid(scene, panel, luminance, bake_options, SurfaceEmitterMethod::kAdaptiveRefine, dx);
    std::printf("[ measured ] moved %.0f cm, %d quick answers\n", -100 * dx, moved.quick);
    EXPECT_EQ(moved.quick, dx > -0.032 ? 1 : 0);
    EXPECT_LE(moved.max, 0.02);
    EXPECT_LE(moved.mean, 0.002);
  }
}

TEST(EmitterGrid, LinksRoundTripThroughAFile) {
  const Bake bake = baker::Baker(Cornell(), Hierarchical()).Bake();
  ASSERT_TRUE(bake.hierarchy && bake.hierarchy->has_grid_links());
  const std::string path = ::testing::TempDir() + "emitter_grid_round_trip.rlb";
  ASSERT_TRUE(WriteBake(bake, path).ok());
  Bake back;
  const Status st = ReadBake(path, &back);
  ASSERT_TRUE(st.ok()) << st.ToString();
  ASSERT_TRUE(back.hierarchy.has_value());
  EXPECT_EQ(back.hierarchy->grid_link_offsets, bake.hierarchy->grid_link_offsets);
  EXPECT_EQ(back.hierarchy->grid_link_node, bake.hierarchy->grid_link_node);
  EXPECT_EQ(back.hierarchy->grid_link_f, bake.hierarchy->grid_link_f);
  std::remove(path.c_str());
}

TEST(EmitterGrid, PlaceDimAndRemoveDoNotAllocateAndRemovalRestoresTheGrid) {
  Engine engine;
  ASSERT_TRUE(engine.Open(baker::Baker(Cornell(), Hierarchical()).Bake()).ok());
  const std::vector<int32_t> before(engine.grid_illuminance(0).raw(),
                                    engine.grid_illuminance(0).raw() + 3 * engine.bake().grids[0].point_count());
  const LightQ12 light[3] = {Light(300), Light(300), Light(300)};
  const LightQ12 dim[3] = {Light(30), Light(30), Light(30)};
  const SurfaceEmitterShape shape = MakeShape(kCeiling.surface, kCeiling.corners);
  g_allocations = 0;
  g_count_allocations = true;
  const Status placed = engine.SetSurfaceEmitter(1, shape, light);
  engine.Update();
  size_t brightest = 0;  // of the points the panel lights
  for (size_t i = 0; i < before.size(); i += 3) {
    const int32_t* now = engine.grid_illuminance(0).raw();
    if (now[i] - before[i] > now[brightest] - before[brightest]) brightest = i;
  }
  const int32_t lit = engine.grid_illuminance(0).raw()[brightest];
  const Status dimmed = engine.SetSurfaceEmitterLuminance(1, dim);
  engine.Update();
  const int32_t dimmed_lux = engine.grid_illuminance(0).raw()[brightest];
  const Status removed = engine.RemoveSurfaceEmitter(1);
  engine.Update();
  g_count_allocations = false;
  EXPECT_TRUE(placed.ok() && dimmed.ok() && removed.ok());
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_GT(lit, before[brightest] + 4096);  // the panel adds more than 1 lux
  EXPECT_LT(dimmed_lux, lit);
  const std::vector<int32_t> after(engine.grid_illuminance(0).raw(),
                                   engine.grid_illuminance(0).raw() + before.size());
  EXPECT_EQ(after, before);
}

}  // namespace
}  // namespace relight::testing
