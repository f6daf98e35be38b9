// Adaptive refine (AR) for run-time emitters: the fixed-point point-to-polygon
// kernel against the baker's float64 one; AR and FE against a reference with
// the emitter's exact first shot (surface_emitter_reference.h) on a polygon
// that cuts leaves; a refine pool too small is an error that changes
// nothing; placements and moves allocate nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "baker_core.h"
#include "count_allocations.h"
#include "form_factors.h"
#include "point_polygon_factor.h"
#include "radiosity_vec.h"
#include "relight/baker/baker.h"
#include "relight/engine/engine.h"
#include "surface_emitter_reference.h"
#include "surface_emitter_test_support.h"
#include "test_scenes.h"

namespace relight::testing {
namespace {

using namespace baker::radiosity_vec;

TEST(PointToPolygonFactor, MatchesTheBakersFloat64Kernel) {
  std::mt19937 rng(15);
  std::uniform_real_distribution<double> u(-1, 1);
  double worst = 0;
  int nonzero = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    // A quad in the plane z = 0 (lit side +z), a point above or beside it
    // with a random normal (so the polygon is often cut by the point's plane).
    const double cx = u(rng), cy = u(rng), sx = 0.05 + std::abs(u(rng)), sy = 0.05 + std::abs(u(rng));
    std::vector<Vec3> poly = {{cx, cy, 0}, {cx + sx, cy + 0.1 * u(rng), 0}, {cx + sx, cy + sy, 0}, {cx - 0.1 * std::abs(u(rng)), cy + sy, 0}};
    const Vec3 x{u(rng), u(rng), (trial % 10 == 0 ? 0.003 : 0.02) + std::abs(u(rng))};
    Vec3 n{u(rng), u(rng), u(rng)};
    n = (1.0 / Length(n)) * n;
    int64_t x_q16[3], poly_q16[4][3];
    int32_t n_q30[3];
    for (int i = 0; i < 3; ++i) {
      x_q16[i] = std::llround(x[i] * 65536);
      n_q30[i] = static_cast<int32_t>(std::lround(n[i] * (1 << 30)));
    }
    // The same geometry in both: the float64 kernel sees the rounded points.
    Vec3 xr{static_cast<double>(x_q16[0]) / 65536.0, static_cast<double>(x_q16[1]) / 65536.0,
             static_cast<double>(x_q16[2]) / 65536.0};
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < 3; ++i) {
        poly_q16[k][i] = std::llround(poly[k][i] * 65536);
        poly[k][i] = static_cast<double>(poly_q16[k][i]) / 65536.0;
      }
    const double want = baker::PointToPolygonFormFactor(xr, n, poly.data(), 4, {0, 0, 1});
    const double got = PointToPolygonFactorQ32(x_q16, n_q30, poly_q16, 4) / 4294967296.0;
    worst = std::max(worst, std::abs(got - want));
    if (want > 0) ++nonzero;
  }
  std::printf("[ measured ] point-to-polygon factor: max |fixed - float64| %.2e over 2000 cases (%d lit)\n",
              worst, nonzero);
  EXPECT_GT(nonzero, 1000);
  EXPECT_LE(worst, 1e-6);
}

LightQ12 Light(double cd_m2) { return LightQ12::FromRaw(static_cast<int32_t>(std::lround(cd_m2 * 4096))); }

void DarkenLuminaires(Engine* engine) {
  for (int i = 0; i < engine->luminaire_count(); ++i)
    ASSERT_TRUE(engine->SetDimmer(i, Q1_15::FromRaw(0)).ok());
}

struct Errors {
  double max = 0, mean = 0;  // of the peak, worst channel
  Eigen::Index worst_vertex = 0;
  double worst_got = 0, worst_want = 0;
};

// The engine's vertex luminance for the shape against the reference, per
// channel, as fractions of the reference's peak.
Errors Measure(Engine* engine, SurfaceEmitterShape shape, SurfaceEmitterMethod method,
               const Eigen::MatrixXd& reference, double luminance) {
  shape.method = method;
  const LightQ12 light[3] = {Light(luminance), Light(luminance), Light(luminance)};
  Errors out;
  const Status st = engine->SetSurfaceEmitter(0, shape, light);
  EXPECT_TRUE(st.ok()) << st.ToString();
  engine->Update();
  const int32_t* got = engine->vertex_luminance().raw();
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd want = luminance * reference.col(c);
    const double peak = want.cwiseAbs().maxCoeff();
    double max_error = 0, sum = 0;
    for (Eigen::Index v = 0; v < want.size(); ++v) {
      const double e = std::abs(got[3 * v + c] / 4096.0 - want(v));
      max_error = std::max(max_error, e);
      sum += e;
    }
    if (max_error / peak > out.max) {
      out.max = max_error / peak;
      Eigen::Index worst = 0;
      for (Eigen::Index v = 0; v < want.size(); ++v)
        if (std::abs(got[3 * v + c] / 4096.0 - want(v)) == max_error) worst = v;
      out.worst_vertex = worst;
      out.worst_got = got[3 * worst + c] / 4096.0;
      out.worst_want = want(worst);
    }
    out.mean = std::max(out.mean, sum / static_cast<double>(want.size()) / peak);
  }
  return out;
}

struct Case {
  const char* surface;
  std::vector<Vec3> polygon;
};

// bake_path: the scene's bake as relight-bake wrote it (same patch size,
// default options), or empty to bake it here.
void CompareOnScene(const std::string& toml, double patch_size, const std::vector<Case>& cases,
                    bool check_bars, const std::string& bake_path = "") {
  baker::Scene scene = baker::LoadScene(toml);
  if (patch_size > 0) scene.patch_size_m = patch_size;
  baker::BakeOptions options;
  options.solver = baker::SolverKind::kHierarchical;
  options.solve_tolerance = 1e-9;
  Engine engine;
  if (bake_path.empty()) {
    ASSERT_TRUE(engine.Open(baker::Baker(scene, options).Bake()).ok());
  } else {
    ASSERT_TRUE(engine.Open(bake_path).ok());
  }
  DarkenLuminaires(&engine);
  const auto core = baker::BuildBakerCore(scene, options, nullptr);
  for (const Case& c : cases) {
    const Eigen::MatrixXd reference = ReferenceEmitterVertexLuminance(*core, c.surface, c.polygon);
    const SurfaceEmitterShape shape = MakeShape(c.surface, c.polygon);
    const Errors fe = Measure(&engine, shape, SurfaceEmitterMethod::kFractionalEmissivity, reference, 100);
    const Errors ar = Measure(&engine, shape, SurfaceEmitterMethod::kAdaptiveRefine, reference, 100);
    const int sweeps = engine.last_update_emitter_sweeps();
    // What route (b) would store: the links leaving this surface's nodes,
    // each pre-refined one or two levels (4 or 16 children links).
    const BakeHierarchy& h = *engine.bake().hierarchy;
    size_t leaving = 0;
    for (uint32_t i = 0; i < h.link_count(); ++i) {
      if (engine.bake().mesh.surface_names[h.node_surface[h.link_p[i]]] == c.surface ||
          engine.bake().mesh.surface_names[h.node_surface[h.link_q[i]]] == c.surface) ++leaving;
    }
    std::printf("[ measured ] %s, emitter on %s (%zu patches): vertex error of peak, FE max %.3f %% mean %.4f %%, "
                "AR max %.3f %% mean %.4f %% (%d sweeps, %d new links; the surface has %zu of the %u links)\n",
                scene.name.c_str(), c.surface, core->mesh.patch_count(), 100 * fe.max, 100 * fe.mean,
                100 * ar.max, 100 * ar.mean, sweeps, engine.last_emitter_refine_links(), leaving, h.link_count());
    for (const Errors* e : {&fe, &ar}) {
      const Vec3& x = core->mesh.positions[static_cast<size_t>(e->worst_vertex)];
      std::printf("[ measured ]   %s worst at (%.3f, %.3f, %.3f) on %s: %.4f cd/m^2, reference %.4f\n",
                  e == &fe ? "FE" : "AR", x[0], x[1], x[2],
                  scene.surfaces[core->mesh.vertex_surface[static_cast<size_t>(e->worst_vertex)]].name.c_str(),
                  e->worst_got, e->worst_want);
    }
    if (check_bars) {
      EXPECT_LT(ar.max, fe.max) << c.surface;
      EXPECT_LT(ar.mean, fe.mean) << c.surface;
      EXPECT_LE(ar.max, 0.02) << c.surface;
      EXPECT_LE(ar.mean, 0.002) << c.surface;
    }
  }
}

// Off the patch grid's lines, so they cut leaves: a panel in the ceiling and
// a window in the back wall (the paper's Fig. 7 setting).
const std::vector<Case> kCornellCases = {
    {"ceiling", {{0.203, -0.221, 0.5488}, {0.361, -0.197, 0.5488}, {0.347, -0.362, 0.5488}, {0.212, -0.338, 0.5488}}},
    {"back_wall", {{0.113, -0.5592, 0.207}, {0.347, -0.5592, 0.221}, {0.338, -0.5592, 0.436}, {0.121, -0.5592, 0.452}}},
};

TEST(SurfaceEmitterAr, CloserToTheExactFirstShotThanFe) {
  CompareOnScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/cornell_box.toml", 0, kCornellCases, true);
}

// The 16k-patch living room (about a minute: it builds the room's links
// twice). Run with RELIGHT_AR_LIVING_ROOM=1, or =BAKE.rlb to open that bake
// of `relight-bake fixtures/living_room.toml --patch-size 0.092 --solver
// hierarchical` instead of baking; docs/hierarchy.md has the figures.
TEST(SurfaceEmitterAr, LivingRoom16k) {
  const char* env = std::getenv("RELIGHT_AR_LIVING_ROOM");
  if (env == nullptr) GTEST_SKIP() << "set RELIGHT_AR_LIVING_ROOM=1 (or =BAKE.rlb)";
  const std::string bake_path = std::string(env) == "1" ? "" : env;
  const std::vector<Case> cases = {
      {"room/+z", {{2.5, 1.5, 2.7}, {3.5, 1.5, 2.7}, {3.0, 2.5, 2.7}}},
      {"room/+z", {{2.53, 1.51, 2.7}, {3.47, 1.56, 2.7}, {3.44, 2.49, 2.7}, {2.49, 2.44, 2.7}}},
      // Windows (the paper's Figs. 7-8): on the free wall +x, on the front wall.
      {"room/+x", {{6.0, 1.21, 0.93}, {6.0, 2.33, 0.97}, {6.0, 2.31, 2.12}, {6.0, 1.19, 2.08}}},
      {"room/-y", {{2.21, 0.0, 0.93}, {3.33, 0.0, 0.97}, {3.31, 0.0, 2.12}, {2.19, 0.0, 2.08}}},
      // One mostly behind the shelf (2 cm from the wall): light through gaps.
      {"room/-x", {{0.0, 1.21, 0.93}, {0.0, 2.33, 0.97}, {0.0, 2.31, 2.12}, {0.0, 1.19, 2.08}}},
  };
  CompareOnScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/living_room.toml", 0.092, cases, false, bake_path);
}

// A small closed box (fast to bake) for the bookkeeping.
Bake BoxBake() {
  baker::BakeOptions options;
  options.solver = baker::SolverKind::kHierarchical;
  return baker::Baker(baker::test_scenes::ClosedBox(0.125, {0.6, 0.5, 0.4}), options).Bake();
}

const std::vector<Vec3> kBoxCeilingEmitter = {{0.3, 0.3, 1}, {0.7, 0.32, 1}, {0.6, 0.7, 1}};

std::vector<int32_t> Luminance(const Engine& engine) {
  return std::vector<int32_t>(engine.vertex_luminance().begin(), engine.vertex_luminance().end());
}

// Where adaptive refine makes no new link (a threshold of 2^0 of the
// emitter's exitance), every link sends the covered fraction with FE's
// source-moment term (surface_emitter_moments.h), so AR's first shot is the
// light FE's gathers take from the emitter: the two pictures agree to the
// solves' tolerance. Without the moment term a partly covered coarse node
// sends as if the emitter sat at its centre: max 0.083 %, mean 0.023 % of
// peak apart (measured; with it 0.035 % and 0.0048 %).
TEST(SurfaceEmitterAr, UnrefinedLinksSendWhatFesGathersDo) {
  EngineOptions options;
  options.emitter_refine_bits = 0;
  Engine engine;
  ASSERT_TRUE(engine.Open(BoxBake(), options).ok());
  const LightQ12 light[3] = {Light(100), Light(100), Light(100)};
  SurfaceEmitterShape shape = MakeShape("ceiling", kBoxCeilingEmitter);
  shape.method = SurfaceEmitterMethod::kFractionalEmissivity;
  ASSERT_TRUE(engine.SetSurfaceEmitter(0, shape, light).ok());
  engine.Update();
  const std::vector<int32_t> fe = Luminance(engine);
  shape.method = SurfaceEmitterMethod::kAdaptiveRefine;
  ASSERT_TRUE(engine.SetSurfaceEmitter(0, shape, light).ok());
  EXPECT_EQ(engine.last_emitter_refine_links(), 0);
  engine.Update();
  const std::vector<int32_t> ar = Luminance(engine);
  double peak = 0, max_gap = 0, sum = 0;
  for (size_t i = 0; i < fe.size(); ++i) {
    peak = std::max(peak, std::abs(fe[i] / 4096.0));
    max_gap = std::max(max_gap, std::abs(ar[i] - fe[i]) / 4096.0);
    sum += std::abs(ar[i] - fe[i]) / 4096.0;
  }
  const double mean_gap = sum / static_cast<double>(fe.size());
  std::printf("[ measured ] AR without new links against FE: max %.4f %% mean %.5f %% of peak (%.2f cd/m^2)\n",
              100 * max_gap / peak, 100 * mean_gap / peak, peak);
  EXPECT_GT(peak, 50);
  EXPECT_LE(max_gap / peak, 5e-4);
  EXPECT_LE(mean_gap / peak, 1e-4);
}

TEST(SurfaceEmitterAr, ThresholdOutsideItsRangeIsAnError) {
  for (int bits : {-1, 33}) {
    EngineOptions options;
    options.emitter_refine_bits = bits;
    Engine engine;
    const Status st = engine.Open(BoxBake(), options);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << bits;
    EXPECT_NE(st.message().find("emitter_refine_bits"), std::string::npos) << st.ToString();
  }
}

TEST(SurfaceEmitterAr, PoolTooSmallIsAnErrorAndChangesNothing) {
  EngineOptions options;
  options.emitter_refine_links = 3;
  Engine engine;
  ASSERT_TRUE(engine.Open(BoxBake(), options).ok());
  const LightQ12 light[3] = {Light(80), Light(80), Light(80)};
  // A triangle inside one leaf of the floor's grid needs few links... but
  // the ceiling triangle cuts many nodes: more than 3 new links.
  SurfaceEmitterShape fe = MakeShape("floor", {{0.2, 0.2, 0}, {0.8, 0.2, 0}, {0.5, 0.8, 0}});
  fe.method = SurfaceEmitterMethod::kFractionalEmissivity;
  ASSERT_TRUE(engine.SetSurfaceEmitter(0, fe, light).ok());
  engine.Update();
  const std::vector<int32_t> before = Luminance(engine);
  const Status st = engine.SetSurfaceEmitter(0, MakeShape("ceiling", kBoxCeilingEmitter), light);
  EXPECT_EQ(st.code(), StatusCode::kOutOfRange) << st.ToString();
  EXPECT_NE(st.message().find("more than the 3 the refine pool holds"), std::string::npos) << st.ToString();
  EXPECT_NE(st.message().find("emitter_refine_links"), std::string::npos) << st.ToString();
  engine.Update();
  EXPECT_EQ(engine.last_update_emitters_solved(), 0);
  EXPECT_EQ(Luminance(engine), before);
  // The same shape as FE needs no pool.
  SurfaceEmitterShape as_fe = MakeShape("ceiling", kBoxCeilingEmitter);
  as_fe.method = SurfaceEmitterMethod::kFractionalEmissivity;
  EXPECT_TRUE(engine.SetSurfaceEmitter(0, as_fe, light).ok());
}

// The first shot's sources are cut in two parts whatever the thread count
// (surface_emitter_refine.h): one, two or three engine threads give the same
// bits for every placement, move and the link count.
TEST(SurfaceEmitterAr, SameBitsOnOneTwoAndThreeThreads) {
  const Bake bake = BoxBake();
  const SurfaceEmitterShape shapes[3] = {MakeShape("ceiling", kBoxCeilingEmitter),
                                         MakeShape("ceiling", {{0.35, 0.3, 1}, {0.75, 0.32, 1}, {0.65, 0.7, 1}}),
                                         MakeShape("floor", {{0.1, 0.1, 0}, {0.9, 0.15, 0}, {0.5, 0.9, 0}})};
  const LightQ12 light[3] = {Light(100), Light(90), Light(80)};
  std::vector<std::vector<int32_t>> want;
  for (int threads : {1, 2, 3}) {
    EngineOptions options;
    options.threads = threads;
    Engine engine;
    ASSERT_TRUE(engine.Open(bake, options).ok());
    ASSERT_EQ(engine.thread_count(), threads);
    std::vector<std::vector<int32_t>> got;
    for (int i = 0; i < 3; ++i) {
      ASSERT_TRUE(engine.SetSurfaceEmitter(i % 2, shapes[i], light).ok());
      engine.Update();
      got.push_back(Luminance(engine));
    }
    if (threads == 1) {
      want = got;
      EXPECT_NE(want[0], want[1]) << "the move changes the picture";
      continue;
    }
    for (int i = 0; i < 3; ++i) EXPECT_EQ(got[i], want[i]) << threads << " threads, placement " << i;
  }
}

// With every change solved at once, and with quick answers and their
// settles (the default, EngineOptions::emitter_quick_changes).
TEST(SurfaceEmitterAr, PlacementsAndMovesDoNotAllocate) {
  for (const bool quick_changes : {false, true}) {
    EngineOptions options;
    options.emitter_quick_changes = quick_changes;
    Engine engine;
    ASSERT_TRUE(engine.Open(BoxBake(), options).ok());
    SurfaceEmitterShape shapes[2] = {MakeShape("ceiling", kBoxCeilingEmitter),
                                     MakeShape("ceiling", {{0.305, 0.3, 1}, {0.705, 0.32, 1}, {0.605, 0.7, 1}})};
    const LightQ12 light[3] = {Light(100), Light(90), Light(80)};
    ASSERT_TRUE(engine.SetSurfaceEmitter(1, shapes[0], light).ok());  // warm up
    UpdateSettled(&engine);
    g_allocations = 0;
    g_count_allocations = true;
    int solved = 0, quick = 0;
    bool ok = true;
    for (int i = 0; i < 20; ++i) {
      ok = ok && engine.SetSurfaceEmitter(i % 3, shapes[i & 1], light).ok();
      engine.Update();
      solved += engine.last_update_emitters_solved();
      quick += engine.last_update_emitters_quick();
    }
    ok = ok && engine.RemoveSurfaceEmitter(1).ok();
    engine.Update();
    engine.Update();  // idle: settles what is left
    const bool settled = engine.emitters_settled();
    g_count_allocations = false;
    EXPECT_TRUE(ok);
    EXPECT_TRUE(settled);
    EXPECT_EQ(g_allocations.load(), 0) << (quick_changes ? "quick answers" : "solved at once");
    if (!quick_changes) {
      // Each slot keeps its last two solutions (surface_emitters.h): slot 0
      // solves both shapes, slot 1 had shape 0 from the warm-up and solves
      // shape 1, slot 2 solves both; every later placement is a restore.
      EXPECT_EQ(solved, 5);
      EXPECT_EQ(quick, 0);
    } else {
      EXPECT_GT(quick, 0);  // moves answered from their start, settled by the restores' Updates
    }
  }
}

}  // namespace
}  // namespace relight::testing
