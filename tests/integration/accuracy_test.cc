// Acceptance figures of the end-to-end slice: the fixed-point engine reading
// a bake file vs the float64 reference solve, on the Cornell box with a cos^10
// spot (spread 90 degrees, SH degree 8). Bars: split mode max <= 2% of the
// scene's peak and mean <= 0.3%; the all-in-SH paper mode is reported.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "cornell_fixture.h"
#include "relight/baker/accuracy.h"
#include "relight/engine/engine.h"

namespace relight::test {
namespace {

std::vector<baker::FixtureSetting> Aimed(const baker::Baker& b, double pan, double tilt) {
  std::vector<baker::FixtureSetting> s = b.DefaultSettings();
  for (auto& f : s) {
    f.pan_deg = pan;
    f.tilt_deg = tilt;
  }
  return s;
}

struct AimCase {
  double pan, tilt;
};

class CornellAccuracy : public ::testing::TestWithParam<AimCase> {};

TEST_P(CornellAccuracy, SplitModeMeetsTheBars) {
  const BakedScene& baked = BakedFixture("cornell_box", baker::DirectModeKind::kExact);
  Engine engine;
  ASSERT_TRUE(engine.Open(baked.bake_path).ok());
  const auto settings = Aimed(*baked.baker, GetParam().pan, GetParam().tilt);
  const baker::ReferenceResult ref = baked.baker->Reference(settings);
  const baker::AccuracyReport r = baker::CompareWithReference(&engine, ref, settings);
  std::printf("[cornell split pan %.0f tilt %.0f] vertices: peak %.3f cd/m2 max %.3f%% mean %.4f%%; "
              "grid: peak %.2f lux max %.3f%% mean %.4f%%\n",
              GetParam().pan, GetParam().tilt, r.vertices.peak, 100 * r.vertices.max_rel,
              100 * r.vertices.mean_rel, r.grids.peak, 100 * r.grids.max_rel, 100 * r.grids.mean_rel);
  EXPECT_GT(r.vertices.peak, 0.0);
  EXPECT_LE(r.vertices.max_rel, 0.02);
  EXPECT_LE(r.vertices.mean_rel, 0.003);
  EXPECT_LE(r.grids.max_rel, 0.02);
  EXPECT_LE(r.grids.mean_rel, 0.003);
}

TEST_P(CornellAccuracy, AllInShModeIsReported) {
  const BakedScene& baked = BakedFixture("cornell_box", baker::DirectModeKind::kAllInSh);
  Engine engine;
  ASSERT_TRUE(engine.Open(baked.bake_path).ok());
  const auto settings = Aimed(*baked.baker, GetParam().pan, GetParam().tilt);
  const baker::ReferenceResult ref = baked.baker->Reference(settings);
  const baker::AccuracyReport r = baker::CompareWithReference(&engine, ref, settings);
  std::printf("[cornell all-in-SH pan %.0f tilt %.0f] vertices: peak %.3f cd/m2 max %.3f%% mean %.4f%%\n",
              GetParam().pan, GetParam().tilt, r.vertices.peak, 100 * r.vertices.max_rel,
              100 * r.vertices.mean_rel);
  // Dobashi report about 20% max for this mode; it must at least resemble the
  // reference (a broken basis or rotation gives errors of order 100%).
  EXPECT_GT(r.vertices.peak, 0.0);
  EXPECT_LE(r.vertices.max_rel, 0.5);
  EXPECT_LE(r.vertices.mean_rel, 0.05);
}

INSTANTIATE_TEST_SUITE_P(Aims, CornellAccuracy,
                         ::testing::Values(AimCase{0, 0}, AimCase{0, 30}, AimCase{45, 60}),
                         [](const ::testing::TestParamInfo<AimCase>& param_info) {
                           return "pan" + std::to_string(static_cast<int>(param_info.param.pan)) + "_tilt" +
                                  std::to_string(static_cast<int>(param_info.param.tilt));
                         });

}  // namespace
}  // namespace relight::test
