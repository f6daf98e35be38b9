// Zoom at run time, end to end: fixtures/cornell_zoom.toml (a Gaussian beam
// zooming 11..60 degrees, lumens held: 11 is the narrowest real zoom of the
// stage's types) baked once at the degree the baker
// picks for the narrowest beam; the fixed-point engine zoomed with SetZoom
// against the float64 reference solve of the beam at the same angle. Bars
// (issue 12): max <= 2 % of the peak, mean <= 0.3 %, at the narrowest,
// middle and widest zoom, on vertices and the floor grid.
#include <cstdio>
#include <string>

#include <gtest/gtest.h>

#include "cornell_fixture.h"
#include "relight/baker/accuracy.h"
#include "relight/baker/beam_profile.h"
#include "relight/baker/lid_error.h"
#include "relight/engine/engine.h"

namespace relight::test {
namespace {

class CornellZoomAccuracy : public ::testing::TestWithParam<double> {};

TEST_P(CornellZoomAccuracy, SplitModeMeetsTheBars) {
  const BakedScene& baked = BakedFixture("cornell_zoom", baker::DirectModeKind::kExact);
  // The degree came from the narrowest beam, not a default: the widest
  // would have needed fewer terms. (An 11-degree Gaussian misplaces more
  // than 2 % of its flux even at degree 22, so the choice is the cap; the
  // exact direct term carries the beam's detail and the bars hold anyway.
  // At the old cap, 16, the grid missed the max bar: docs/accuracy.md.)
  ASSERT_EQ(baked.baker->report().zoom_degrees.size(), 1u);
  const baker::LuminaireDegree& chosen = baked.baker->report().zoom_degrees[0];
  EXPECT_EQ(baked.bake.luminaires[0].sh_degree, chosen.choice.degree);
  const baker::Lid& lid = baked.scene.luminaires[0].lid;
  const baker::DegreeChoice widest =
      baker::ChooseShDegree(baker::LidErrorModel(baker::ZoomedBeamLid(lid, lid.zoom_max_deg)),
                            baker::kZoomDegreeTarget, chosen.window, chosen.measure);
  EXPECT_TRUE(widest.met);
  EXPECT_LT(widest.degree, chosen.choice.degree);

  Engine engine;
  ASSERT_TRUE(engine.Open(baked.bake_path).ok());
  std::vector<baker::FixtureSetting> settings = baked.baker->DefaultSettings();
  settings[0].zoom_deg = GetParam();
  const baker::ReferenceResult ref = baked.baker->Reference(settings);
  const baker::AccuracyReport r = baker::CompareWithReference(&engine, ref, settings);
  EXPECT_EQ(engine.state(0).zoom_deg.raw(), static_cast<int32_t>(GetParam() * 65536));
  std::printf("[cornell zoom %.1f deg, SH degree %d] vertices: peak %.3f cd/m2 max %.3f%% mean "
              "%.4f%%; grid: peak %.2f lux max %.3f%% mean %.4f%%\n",
              GetParam(), chosen.choice.degree, r.vertices.peak, 100 * r.vertices.max_rel,
              100 * r.vertices.mean_rel, r.grids.peak, 100 * r.grids.max_rel, 100 * r.grids.mean_rel);
  EXPECT_GT(r.vertices.peak, 0.0);
  EXPECT_LE(r.vertices.max_rel, 0.02);
  EXPECT_LE(r.vertices.mean_rel, 0.003);
  EXPECT_LE(r.grids.max_rel, 0.02);
  EXPECT_LE(r.grids.mean_rel, 0.003);
}

// A zoom is a change of the light, not a rescaling of it: the narrow beam's
// reference differs from the wide one's far beyond the bars, so the test
// above could not pass by accident with the zoom ignored.
TEST(CornellZoom, ZoomChangesTheLightBeyondTheBars) {
  const BakedScene& baked = BakedFixture("cornell_zoom", baker::DirectModeKind::kExact);
  Engine engine;
  ASSERT_TRUE(engine.Open(baked.bake_path).ok());
  std::vector<baker::FixtureSetting> narrow = baked.baker->DefaultSettings(), wide = narrow;
  narrow[0].zoom_deg = 11;
  wide[0].zoom_deg = 60;
  const baker::ReferenceResult ref_narrow = baked.baker->Reference(narrow);
  const baker::AccuracyReport r = baker::CompareWithReference(&engine, ref_narrow, wide);
  std::printf("[cornell zoom] engine at 60 deg vs reference at 11 deg: max %.1f%% mean %.2f%%\n",
              100 * r.vertices.max_rel, 100 * r.vertices.mean_rel);
  EXPECT_GT(r.vertices.max_rel, 0.2);
  EXPECT_GT(r.vertices.mean_rel, 0.003);
}

// The reference takes a beam angle only where there is a zoom (issue 12):
// set on a fixed beam it is an error naming the scene's line, not silently
// dropped; past a zoom's range it clamps, as the engine does.
TEST(CornellZoom, TheReferenceRefusesAZoomForAFixedBeamAndClampsPastTheRange) {
  const BakedScene& fixed = BakedFixture("cornell_box", baker::DirectModeKind::kExact);
  std::vector<baker::FixtureSetting> settings = fixed.baker->DefaultSettings();
  settings[0].zoom_deg = 20;
  try {
    (void)fixed.baker->Reference(settings);
    ADD_FAILURE() << "a zoom on a fixed beam was accepted";
  } catch (const baker::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("cornell_box.toml:" + std::to_string(fixed.scene.luminaires[0].line) +
                                         ": reference: luminaire 'spot' has no zoom"),
              std::string::npos)
        << e.what();
  }

  const BakedScene& zoom = BakedFixture("cornell_zoom", baker::DirectModeKind::kExact);
  std::vector<baker::FixtureSetting> below = zoom.baker->DefaultSettings(), narrowest = below;
  below[0].zoom_deg = 5;
  narrowest[0].zoom_deg = 11;
  const baker::ReferenceResult a = zoom.baker->Reference(below), b = zoom.baker->Reference(narrowest);
  EXPECT_TRUE(a.vertex_luminance == b.vertex_luminance);
  EXPECT_TRUE(a.grid_illuminance == b.grid_illuminance);
}

INSTANTIATE_TEST_SUITE_P(Zooms, CornellZoomAccuracy, ::testing::Values(11.0, 12.0, 15.0, 35.5, 60.0),
                         [](const ::testing::TestParamInfo<double>& param_info) {
                           return "zoom" + std::to_string(static_cast<int>(param_info.param));
                         });

}  // namespace
}  // namespace relight::test
