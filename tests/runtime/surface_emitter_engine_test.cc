// Run-time emitters through the engine: the fixed-point solve over the bake's
// stored links against the baker's own float64 hierarchical solve of the same
// emission (HierarchicalSolver::Solve, vertex values by AverageToVertices), a
// luminance change that only rescales, and bad input that changes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "baker_core.h"
#include "count_allocations.h"
#include "radiosity_vec.h"
#include "relight/baker/baker.h"
#include "relight/engine/engine.h"
#include "surface_emitter_test_support.h"
#include "test_scenes.h"

namespace relight::testing {
namespace {

using namespace baker::radiosity_vec;

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

// A quadrilateral across several ceiling nodes of the Cornell box, off the
// patch grid's lines.
const std::vector<Vec3> kCeilingEmitter = {
    {0.203, -0.221, 0.5488}, {0.361, -0.197, 0.5488}, {0.347, -0.362, 0.5488}, {0.212, -0.338, 0.5488}};

TEST(SurfaceEmitterSolve, MatchesTheBakersFloat64Solve) {
  const baker::Scene scene = baker::LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/cornell_box.toml");
  baker::Baker baker(scene, Hierarchical());
  Engine engine;
  ASSERT_TRUE(engine.Open(baker.Bake()).ok());
  DarkenLuminaires(&engine);
  const double luminance[3] = {200, 120, 45};  // cd/m^2, a warm white
  const LightQ12 light[3] = {Light(luminance[0]), Light(luminance[1]), Light(luminance[2])};
  SurfaceEmitterShape shape = MakeShape("ceiling", kCeilingEmitter);
  shape.method = SurfaceEmitterMethod::kFractionalEmissivity;  // the reference is FE's emission
  ASSERT_TRUE(engine.SetSurfaceEmitter(0, shape, light).ok());
  engine.Update();
  EXPECT_EQ(engine.last_update_emitters_solved(), 1);
  const int32_t* got = engine.vertex_luminance().raw();

  // Reference: the emitter's covered fraction of each patch (float64 clip),
  // emitting pi L, solved by the baker's hierarchical solver.
  const auto core = baker::BuildBakerCore(scene, Hierarchical(), nullptr);
  const baker::Mesh& mesh = core->mesh;
  const AxisPlane plane({0, 0, 1});
  const std::vector<Vec2> clip = plane.Polygon(kCeilingEmitter);
  uint32_t ceiling = 0;
  while (scene.surfaces[ceiling].name != "ceiling") ++ceiling;
  Eigen::VectorXd fraction = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.patch_count()));
  for (size_t i = 0; i < mesh.patch_count(); ++i) {
    const baker::Patch& p = mesh.patches[i];
    if (p.surface != ceiling) continue;
    std::vector<Vec3> corners;
    for (int k = 0; k < p.corner_count; ++k) corners.push_back(mesh.positions[p.vertices[k]]);
    const std::vector<Vec2> patch = plane.Polygon(corners);
    const std::vector<Vec2> cut = ClipConvex(patch, clip);
    if (cut.size() >= 3) fraction(static_cast<Eigen::Index>(i)) = SignedArea(cut) / SignedArea(patch);
  }
  ASSERT_GT(fraction.sum(), 1.0);
  double worst = 0, worst_mean = 0;
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd exitance = core->hierarchical_solver->Solve(c, kPi * luminance[c] * fraction);
    const Eigen::VectorXd want = baker::AverageToVertices(mesh, exitance).col(0) / kPi;
    const double peak = want.cwiseAbs().maxCoeff();
    double max_error = 0, sum_error = 0;
    for (Eigen::Index v = 0; v < want.size(); ++v) {
      const double e = std::abs(got[3 * v + c] / 4096.0 - want(v));
      max_error = std::max(max_error, e);
      sum_error += e;
    }
    const double mean_error = sum_error / static_cast<double>(want.size());
    std::printf("[ measured ] channel %d: peak %.3f cd/m^2, vertex luminance max error %.2e of peak, "
                "mean %.2e of peak\n", c, peak, max_error / peak, mean_error / peak);
    EXPECT_LE(max_error, 0.01 * peak);
    EXPECT_LE(mean_error, 0.001 * peak);
    // The interreflected light matters too: the far walls get some of it.
    worst = std::max(worst, max_error / peak);
    worst_mean = std::max(worst_mean, mean_error / peak);
  }
  std::printf("[ measured ] %d sweeps over %u nodes, %u links; worst max %.2e, worst mean %.2e\n",
              engine.last_update_emitter_sweeps(), engine.bake().hierarchy->node_count(),
              engine.bake().hierarchy->link_count(), worst, worst_mean);
  RecordProperty("vertex_max_error_over_peak", std::to_string(worst));
  RecordProperty("vertex_mean_error_over_peak", std::to_string(worst_mean));
}

// A small closed box (fast to bake) for the engine's bookkeeping.
Bake BoxBake(bool store_hierarchy) {
  baker::BakeOptions options;
  options.solver = baker::SolverKind::kHierarchical;
  options.store_hierarchy = store_hierarchy;
  baker::Scene scene = baker::test_scenes::ClosedBox(0.125, {0.6, 0.5, 0.4});
  if (!store_hierarchy) {
    // Without links for emitters, a bake needs a luminaire (else nothing to bake).
    baker::Luminaire lamp;
    lamp.name = "lamp";
    lamp.position = {0.5, 0.5, 0.9};
    lamp.sh_degree = 1;
    scene.luminaires = {lamp};
  }
  return baker::Baker(scene, options).Bake();
}

const std::vector<Vec3> kBoxCeilingEmitter = {{0.3, 0.3, 1}, {0.7, 0.32, 1}, {0.6, 0.7, 1}};

std::vector<int32_t> Luminance(const Engine& engine) {
  return std::vector<int32_t>(engine.vertex_luminance().begin(), engine.vertex_luminance().end());
}

TEST(SurfaceEmitterEngine, LuminanceChangeRescalesWithoutASolve) {
  Engine engine;
  ASSERT_TRUE(engine.Open(BoxBake(true)).ok());
  const std::vector<int32_t> base = Luminance(engine);
  const LightQ12 light[3] = {Light(100), Light(100), Light(100)};
  ASSERT_TRUE(engine.SetSurfaceEmitter(3, MakeShape("ceiling", kBoxCeilingEmitter), light).ok());
  engine.Update();
  EXPECT_EQ(engine.last_update_emitters_solved(), 1);
  UpdateSettled(&engine);  // a quick answer settled first: a rescale of it must not solve
  const std::vector<int32_t> full = Luminance(engine);
  const LightQ12 half[3] = {Light(50), Light(25), Light(0)};
  ASSERT_TRUE(engine.SetSurfaceEmitterLuminance(3, half).ok());
  engine.Update();
  EXPECT_EQ(engine.last_update_emitters_solved(), 0);
  EXPECT_EQ(engine.last_update_luminaires_recombined(), 0);
  const std::vector<int32_t> dimmed = Luminance(engine);
  int32_t peak = 0;
  for (size_t i = 0; i < full.size(); ++i) {
    const double scale = (i % 3 == 0) ? 0.5 : (i % 3 == 1) ? 0.25 : 0.0;
    EXPECT_NEAR(dimmed[i] - base[i], scale * (full[i] - base[i]), 2.0) << i;
    peak = std::max(peak, full[i] - base[i]);
  }
  EXPECT_GT(peak, 100 * 4096 / 2);  // the emitter's own vertices are bright
  ASSERT_TRUE(engine.RemoveSurfaceEmitter(3).ok());
  engine.Update();
  EXPECT_EQ(Luminance(engine), base);
}

TEST(SurfaceEmitterEngine, PlaceSolveDimAndRemoveDoNotAllocate) {
  Engine engine;
  ASSERT_TRUE(engine.Open(BoxBake(true)).ok());
  const SurfaceEmitterShape shape = MakeShape("ceiling", kBoxCeilingEmitter);
  const LightQ12 light[3] = {Light(100), Light(90), Light(80)};
  g_allocations = 0;
  g_count_allocations = true;
  const Status placed = engine.SetSurfaceEmitter(2, shape, light);
  engine.Update();
  const int solved = engine.last_update_emitters_solved();
  const Status dimmed = engine.SetSurfaceEmitterLuminance(2, light);
  engine.Update();
  const Status removed = engine.RemoveSurfaceEmitter(2);
  engine.Update();
  g_count_allocations = false;
  EXPECT_TRUE(placed.ok() && dimmed.ok() && removed.ok());
  EXPECT_EQ(solved, 1);
  EXPECT_EQ(g_allocations.load(), 0);
}

TEST(SurfaceEmitterEngine, BadInputIsAnErrorAndChangesNothing) {
  Engine engine;
  ASSERT_TRUE(engine.Open(BoxBake(true)).ok());
  const LightQ12 light[3] = {Light(80), Light(80), Light(80)};
  ASSERT_TRUE(engine.SetSurfaceEmitter(0, MakeShape("ceiling", kBoxCeilingEmitter), light).ok());
  UpdateSettled(&engine);
  const std::vector<int32_t> before = Luminance(engine);
  const auto expect_error = [&](StatusCode code, const Status& st, const char* words) {
    EXPECT_EQ(st.code(), code) << st.ToString();
    EXPECT_NE(st.message().find(words), std::string::npos) << st.ToString();
    engine.Update();
    EXPECT_EQ(engine.last_update_emitters_solved(), 0);
    EXPECT_EQ(Luminance(engine), before);
  };
  // 3 mm below the ceiling's plane at one corner.
  expect_error(StatusCode::kInvalidArgument,
               engine.SetSurfaceEmitter(0, MakeShape("ceiling", {{0.3, 0.3, 1}, {0.7, 0.3, 0.997}, {0.6, 0.7, 1}}), light),
               "off the surface's plane");
  expect_error(StatusCode::kNotFound,
               engine.SetSurfaceEmitter(0, MakeShape("skylight", kBoxCeilingEmitter), light), "skylight");
  expect_error(StatusCode::kInvalidArgument,
               engine.SetSurfaceEmitter(kMaxSurfaceEmitters, MakeShape("ceiling", kBoxCeilingEmitter), light),
               "slot 8");
  expect_error(StatusCode::kInvalidArgument, engine.SetSurfaceEmitter(-1, MakeShape("ceiling", kBoxCeilingEmitter), light),
               "slot -1");
  // A bow tie: corners out of order.
  expect_error(StatusCode::kInvalidArgument,
               engine.SetSurfaceEmitter(0, MakeShape("ceiling", {{0.2, 0.2, 1}, {0.8, 0.8, 1}, {0.8, 0.2, 1}, {0.2, 0.8, 1}}), light),
               "not strictly convex");
  expect_error(StatusCode::kInvalidArgument,
               engine.SetSurfaceEmitter(0, MakeShape("ceiling", {{0.2, 0.2, 1}, {0.5, 0.5, 1}, {0.8, 0.8, 1}}), light),
               "not strictly convex");
  expect_error(StatusCode::kInvalidArgument,
               engine.SetSurfaceEmitter(0, MakeShape("ceiling", {{1.2, 0.2, 1}, {1.8, 0.2, 1}, {1.5, 0.8, 1}}), light),
               "does not overlap");
  expect_error(StatusCode::kInvalidArgument,
               engine.SetSurfaceEmitter(0, MakeShape("ceiling", {{0.2, 0.2, 1}, {0.8, 0.2, 1}}), light), "3 to 8 corners");
  const LightQ12 negative[3] = {Light(80), Light(-1), Light(80)};
  expect_error(StatusCode::kInvalidArgument,
               engine.SetSurfaceEmitter(1, MakeShape("ceiling", kBoxCeilingEmitter), negative), "luminance");
  expect_error(StatusCode::kInvalidArgument, engine.SetSurfaceEmitterLuminance(0, negative), "luminance");
  // All slots can be used; the ninth has no slot (above).
  for (int slot = 1; slot < kMaxSurfaceEmitters; ++slot)
    EXPECT_TRUE(engine.SetSurfaceEmitter(slot, MakeShape("floor", {{0.2, 0.2, 0}, {0.8, 0.2, 0}, {0.5, 0.8, 0}}), light).ok());
  engine.Update();
  EXPECT_EQ(engine.last_update_emitters_solved(), kMaxSurfaceEmitters - 1);
}

TEST(SurfaceEmitterEngine, BakeWithoutHierarchyIsUnsupported) {
  Engine engine;
  ASSERT_TRUE(engine.Open(BoxBake(false)).ok());
  ASSERT_FALSE(engine.bake().hierarchy.has_value());
  const std::vector<int32_t> before = Luminance(engine);
  const LightQ12 light[3] = {Light(80), Light(80), Light(80)};
  const Status st = engine.SetSurfaceEmitter(0, MakeShape("ceiling", kBoxCeilingEmitter), light);
  EXPECT_EQ(st.code(), StatusCode::kUnsupported);
  EXPECT_NE(st.message().find("no radiosity hierarchy"), std::string::npos) << st.ToString();
  EXPECT_EQ(engine.SetSurfaceEmitterLuminance(0, light).code(), StatusCode::kUnsupported);
  EXPECT_EQ(engine.RemoveSurfaceEmitter(0).code(), StatusCode::kUnsupported);
  engine.Update();
  EXPECT_EQ(Luminance(engine), before);
}

}  // namespace
}  // namespace relight::testing
