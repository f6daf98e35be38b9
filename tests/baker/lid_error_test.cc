// LID error of truncated, windowed SH series against closed forms; degree
// choice from an error target; beam editing on tables (control points); the
// polar plot's SVG.
#include "relight/baker/lid_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "relight/baker/analytic_photometry.h"
#include "relight/baker/beam_edit.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/photometry.h"
#include "relight/baker/polar_plot.h"
#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

Lid CosLid(double exponent) {
  Lid lid;
  lid.kind = LidKind::kCosPower;
  lid.exponent = exponent;
  lid.spread_deg = 180;  // cos^k clamped at 0: not band-limited for odd k
  lid.peak_cd = 1000;
  return lid;
}

// An isotropic LID is the l = 0 term alone: every measure is 0 from N = 0 on.
TEST(LidError, IsotropicIsExactAtDegreeZero) {
  Lid lid;
  lid.kind = LidKind::kIsotropic;
  lid.peak_cd = 50;
  const LidErrorModel model(lid);
  EXPECT_NEAR(model.coefficients()[0], 50 * std::sqrt(4 * 3.14159265358979323846), 1e-6);
  for (LidErrorMeasure m : {LidErrorMeasure::kL2, LidErrorMeasure::kZonalFlux}) {
    EXPECT_LT(model.Error(0, ShWindow::kNone, m), 1e-9);
  }
}

// I = 1000 max(cos, 0)^2 over the whole sphere: its series converges
// slowly (the clamp at 90 degrees), the error falls with N, and the
// least-squares (no window) series has the smallest L2 error at each N.
TEST(LidError, FallsWithDegreeAndNoWindowIsTheL2Optimum) {
  const LidErrorModel model(CosLid(2));
  double previous = 1e9;
  for (int n = 0; n <= 16; n += 2) {
    const double e = model.Error(n, ShWindow::kNone, LidErrorMeasure::kL2);
    EXPECT_LT(e, previous) << n;
    previous = e;
    for (ShWindow w : {ShWindow::kSigma, ShWindow::kHanning, ShWindow::kLanczos, ShWindow::kSloan}) {
      EXPECT_GE(model.Error(n, w, LidErrorMeasure::kL2) + 1e-12, e) << n << " " << ShWindowName(w);
    }
  }
  // cos^2 on the upper half: a degree-2 polynomial there, so the series of
  // the clamped beam is within a few per cent already at N = 4.
  EXPECT_LT(model.Error(4, ShWindow::kNone, LidErrorMeasure::kL2), 0.05);
  // Windows trade accuracy for less ringing.
  EXPECT_GT(model.MinimumRelative(4, ShWindow::kSigma), model.MinimumRelative(4, ShWindow::kNone));
}

TEST(LidError, WindowFactorsAreTheDocumentedFormulas) {
  const double pi = 3.14159265358979323846;
  EXPECT_DOUBLE_EQ(ShWindowFactor(ShWindow::kSigma, 8, 3), std::sin(pi * 3 / 9) / (pi * 3 / 9));
  EXPECT_DOUBLE_EQ(ShWindowFactor(ShWindow::kSigma, 8, 3), SigmaFactor(8, 3));
  EXPECT_DOUBLE_EQ(ShWindowFactor(ShWindow::kHanning, 8, 3), 0.5 * (1 + std::cos(pi * 3 / 9)));
  EXPECT_DOUBLE_EQ(ShWindowFactor(ShWindow::kSloan, 8, 8), 0.5);
  for (ShWindow w : {ShWindow::kNone, ShWindow::kSigma, ShWindow::kHanning, ShWindow::kLanczos,
                     ShWindow::kSloan}) {
    EXPECT_EQ(ShWindowFactor(w, 5, 0), 1.0);
    EXPECT_EQ(ParseShWindow(ShWindowName(w)), w);
  }
  EXPECT_THROW(ParseShWindow("kaiser"), std::invalid_argument);
}

TEST(LidError, ChoosesTheSmallestDegreeThatMeetsTheTarget) {
  const LidErrorModel model(CosLid(8));
  const DegreeChoice c = ChooseShDegree(model, 0.02, ShWindow::kNone, LidErrorMeasure::kZonalFlux);
  ASSERT_TRUE(c.met);
  EXPECT_LE(c.error, 0.02);
  EXPECT_GT(model.Error(c.degree - 1, ShWindow::kNone, LidErrorMeasure::kZonalFlux), 0.02);
  const DegreeChoice impossible = ChooseShDegree(model, 1e-9, ShWindow::kNone, LidErrorMeasure::kL2);
  EXPECT_FALSE(impossible.met);
  EXPECT_EQ(impossible.degree, kMaxShDegree);

  Scene scene;
  Luminaire a, b;
  a.name = "wide";
  a.lid = CosLid(1);
  b.name = "narrow";
  b.lid = CosLid(40);
  scene.luminaires = {a, b};
  const auto degrees = ApplyLidErrorTarget(&scene, 0.05, DirectModeKind::kExact);
  ASSERT_EQ(degrees.size(), 2u);
  EXPECT_LT(scene.luminaires[0].sh_degree, scene.luminaires[1].sh_degree);
  EXPECT_EQ(degrees[1].measure, LidErrorMeasure::kZonalFlux);
  EXPECT_EQ(ApplyLidErrorTarget(&scene, 0.05, DirectModeKind::kAllInSh)[0].window, ShWindow::kSigma);
}

TEST(BeamEdit, ControlPointsSetKnotsAndInsertNewOnes) {
  PhotometricTable t = PhotometricFixtures()[2].table;  // bilateral, 19 planes
  const double before_other = t.Evaluate(30, 20);
  ApplyControlPoint(ParseControlPoint("10:21.25=777"), &t);  // a new gamma on plane C 10
  EXPECT_EQ(t.gammas(), 74u);
  EXPECT_DOUBLE_EQ(t.Evaluate(10, 21.25), 777.0);
  EXPECT_NEAR(t.Evaluate(30, 20), before_other, 1e-9);  // other planes keep their curves
  ApplyControlPoint(ParseControlPoint("0=1234"), &t);    // a knot, every plane
  for (double c : t.c_deg) EXPECT_DOUBLE_EQ(t.Evaluate(c, 0), 1234.0);
  EXPECT_THROW(ApplyControlPoint(ParseControlPoint("15:20=5"), &t), std::invalid_argument);
  EXPECT_THROW(ApplyControlPoint(ParseControlPoint("190=5"), &t), std::invalid_argument);
  EXPECT_THROW(ParseControlPoint("20"), std::invalid_argument);
  EXPECT_THROW(ParseControlPoint("20=abc"), std::invalid_argument);
  // The edited table writes and reads back.
  const PhotometricTable again = ParseIes(WriteIes(t, "LM-63-2002"), "edited.ies");
  EXPECT_NEAR(again.Evaluate(10, 21.25), 777.0, 1e-6);
}

TEST(PolarPlot, SvgHasTheFileAndOneSeriesPerWindow) {
  PolarPlotOptions o;
  o.title = "oval";
  o.degree = 6;
  o.windows = {ShWindow::kNone, ShWindow::kSigma};
  const std::string svg = LidPolarSvg(MakeLid(PhotometricFixtures()[1].table), o);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  size_t paths = 0;
  for (size_t at = svg.find("<path"); at != std::string::npos; at = svg.find("<path", at + 1)) ++paths;
  EXPECT_EQ(paths, 6u);  // (file + 2 series) x 2 planes
  EXPECT_NE(svg.find("window sigma"), std::string::npos);
}

}  // namespace
}  // namespace relight::baker
