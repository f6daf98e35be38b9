// Chandran & Srivastava's scenario (Figs. 7-9) on fixtures/chandran_room.toml:
// a window-shaped light on the southern wall, a second on the eastern wall,
// then the first switched off. After each step the engine's FE solve is
// compared per vertex with the naive method (the room re-solved in float64,
// dense, with the windows as real emission: baker/src/naive_emitter.h), and
// switching the first off must leave exactly the bits of the second alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "baker_core.h"
#include "naive_emitter.h"
#include "relight/baker/baker.h"
#include "relight/engine/engine.h"
#include "surface_emitter_test_support.h"

namespace relight::testing {
namespace {

struct Window {
  const char* surface;
  std::vector<Vec3> corners;
  double cd_m2;
};

// As the fixture's header gives them.
const Window kSouth = {"front_wall", {{0.12, 0, 0.2}, {0.42, 0, 0.2}, {0.42, 0, 0.46}, {0.12, 0, 0.46}}, 2000};
const Window kEast = {"right_wall", {{0, -0.15, 0.22}, {0, -0.4, 0.22}, {0, -0.4, 0.42}, {0, -0.15, 0.42}}, 1500};

LightQ12 Light(double cd_m2) { return LightQ12::FromRaw(static_cast<int32_t>(std::lround(cd_m2 * 4096))); }

Status Place(Engine* engine, int slot, const Window& w) {
  const LightQ12 l[3] = {Light(w.cd_m2), Light(w.cd_m2), Light(w.cd_m2)};
  return engine->SetSurfaceEmitter(slot, MakeShape(w.surface, w.corners), l);
}

baker::NaiveEmitter Naive(const Window& w) {
  baker::NaiveEmitter e;
  e.surface = w.surface;
  const SurfaceEmitterShape shape = MakeShape(w.surface, w.corners);  // the engine's Q16 corners
  for (int k = 0; k < shape.corner_count; ++k)
    e.corners_m.push_back({shape.corners_q16[k][0] / 65536.0, shape.corners_q16[k][1] / 65536.0,
                           shape.corners_q16[k][2] / 65536.0});
  e.luminance_cd_m2 = {w.cd_m2, w.cd_m2, w.cd_m2};
  return e;
}

std::vector<int32_t> Luminance(const Engine& engine) {
  return std::vector<int32_t>(engine.vertex_luminance().begin(), engine.vertex_luminance().end());
}

TEST(SurfaceEmitterScenario, WindowsAppearAndOneGoesOffAgainstTheNaiveSolve) {
  const baker::Scene scene = baker::LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/chandran_room.toml");
  baker::BakeOptions fe_options;
  fe_options.solver = baker::SolverKind::kHierarchical;
  Engine engine;
  ASSERT_TRUE(engine.Open(baker::Baker(scene, fe_options).Bake()).ok());
  for (int i = 0; i < engine.luminaire_count(); ++i) ASSERT_TRUE(engine.SetDimmer(i, Q1_15::FromRaw(0)).ok());
  baker::BakeOptions naive_options;
  naive_options.solver = baker::SolverKind::kDense;
  const auto core = baker::BuildBakerCore(scene, naive_options, nullptr);
  ASSERT_TRUE(core->solver != nullptr);

  struct Step {
    const char* label;
    std::vector<Window> lit;
  };
  const Step steps[3] = {{"Fig. 7: south window", {kSouth}},
                         {"Fig. 8: + east window", {kSouth, kEast}},
                         {"Fig. 9: south off", {kEast}}};
  for (int s = 0; s < 3; ++s) {
    const Status changed = s == 0   ? Place(&engine, 0, kSouth)
                           : s == 1 ? Place(&engine, 1, kEast)
                                    : engine.RemoveSurfaceEmitter(0);
    ASSERT_TRUE(changed.ok()) << changed.ToString();
    engine.Update();
    std::vector<baker::NaiveEmitter> naive;
    for (const Window& w : steps[s].lit) naive.push_back(Naive(w));
    const Eigen::MatrixXd want = baker::NaiveEmitterVertexLuminance(*core, naive);
    ASSERT_EQ(static_cast<size_t>(want.rows()), engine.bake().mesh.vertex_count());
    const int32_t* got = engine.vertex_luminance().raw();
    double worst_max = 0, worst_mean = 0;
    for (int c = 0; c < 3; ++c) {
      const double peak = want.col(c).maxCoeff();
      double max_e = 0, sum_e = 0;
      for (Eigen::Index v = 0; v < want.rows(); ++v) {
        const double e = std::abs(got[3 * v + c] / 4096.0 - want(v, c));
        max_e = std::max(max_e, e);
        sum_e += e;
      }
      worst_max = std::max(worst_max, max_e / peak);
      worst_mean = std::max(worst_mean, sum_e / static_cast<double>(want.rows()) / peak);
    }
    std::printf("[ measured ] %s: AR (the default method) vs naive (dense, %zu patches), worst channel: "
                "max %.3f %%, mean %.4f %% of peak over %lld vertices; %d solved, %d sweeps\n",
                steps[s].label, core->mesh.patch_count(), 100 * worst_max, 100 * worst_mean,
                static_cast<long long>(want.rows()), engine.last_update_emitters_solved(),
                engine.last_update_emitter_sweeps());
    // FE has no bar of its own (issue 15 reports it); these catch a broken
    // solve: measured 0.36-0.5 % max, 0.05-0.08 % mean. The answer measured
    // is the first one shown (a quick one for a new AR light).
    EXPECT_LE(worst_max, 0.01);
    EXPECT_LE(worst_mean, 0.002);
    UpdateSettled(&engine);  // the next step starts from a still scene
  }
  EXPECT_EQ(engine.last_update_emitters_solved(), 0);  // switching off solves nothing
  // Off means gone: the bits of the east window alone.
  const std::vector<int32_t> after = Luminance(engine);
  Engine east_only;
  ASSERT_TRUE(east_only.Open(Bake(engine.bake())).ok());
  for (int i = 0; i < east_only.luminaire_count(); ++i) ASSERT_TRUE(east_only.SetDimmer(i, Q1_15::FromRaw(0)).ok());
  ASSERT_TRUE(Place(&east_only, 1, kEast).ok());
  UpdateSettled(&east_only);
  EXPECT_EQ(Luminance(east_only), after);
}

}  // namespace
}  // namespace relight::testing
