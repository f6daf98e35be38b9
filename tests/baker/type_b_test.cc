// IES type B (floodlight) files: read, resampled to relight's (C, gamma)
// frame, checked against the analytic beam the fixture was sampled from.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "relight/baker/analytic_photometry.h"
#include "relight/baker/photometric_file.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRad = kPi / 180.0;

// Type B angles of the direction at (C, gamma), from the convention in
// type_b_photometry.h written out again: f = beam, u = C 0, l = C 90,
// H = asin(-d.l) (positive to the right), V = atan2(d.u, d.f).
void TypeBAngles(double c_deg, double gamma_deg, double* h_deg, double* v_deg) {
  const double f = std::cos(gamma_deg * kRad);
  const double u = std::sin(gamma_deg * kRad) * std::cos(c_deg * kRad);
  const double l = std::sin(gamma_deg * kRad) * std::sin(c_deg * kRad);
  *h_deg = std::asin(-l) / kRad;
  *v_deg = std::atan2(u, f) / kRad;
}

// Flux of the analytic flood: in type B angles dOmega = cos H dH dV.
double AnalyticFlux(double h_peak) {
  const int n = 1440;
  const double step = 180.0 / n;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double h = -90 + (i + 0.5) * step, v = -90 + (j + 0.5) * step;
      sum += AnalyticTypeBFlood(h, v, h_peak) * std::cos(h * kRad);
    }
  }
  return sum * (step * kRad) * (step * kRad);
}

TEST(TypeBPhotometry, CommittedFixtureIsWhatTheGeneratorWrites) {
  std::ifstream in(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/photometry/" + kTypeBFloodFile,
                   std::ios::binary);
  ASSERT_TRUE(in) << "run: relight-lid fixtures fixtures/photometry";
  std::ostringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), TypeBFloodIes(false));
}

TEST(TypeBPhotometry, ResampledTableFollowsTheFloodAndKeepsItsFlux) {
  const PhotometricTable t = ParseIes(TypeBFloodIes(false), "flood.ies");
  EXPECT_EQ(t.photometric_type, "B");
  EXPECT_EQ(t.symmetry, CSymmetry::kNone);
  EXPECT_EQ(t.lamp_lumens, 0);  // absolute photometry
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> c_dist(0, 360), g_dist(0, 89.5);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    const double c = c_dist(rng), g = g_dist(rng);
    double h = 0, v = 0;
    TypeBAngles(c, g, &h, &v);
    worst = std::max(worst, std::fabs(t.Evaluate(c, g) - AnalyticTypeBFlood(h, v, 10)));
  }
  // Two bilinear steps (the file's 2.5-degree grid, then the C/gamma grid)
  // on a Gaussian of 12 degrees: ~1 % of the peak each.
  std::printf("[ measured ] type B flood resampled: max |error| %.2f cd of 2000 (%.2f %%)\n", worst,
              worst / 20);
  EXPECT_LE(worst, 0.03 * 2000);
  EXPECT_EQ(t.Evaluate(90, 120), 0);  // behind the flood
  EXPECT_EQ(t.Evaluate(0, 179), 0);

  // The peak sits 5 degrees up (C 0) and 10 degrees to the right (C 270):
  // C = atan2(-sin 10, cos 10 sin 5) = 296.3, gamma = acos(cos 10 cos 5) = 11.2.
  size_t best = 0;
  for (size_t i = 0; i < t.candela.size(); ++i) best = t.candela[i] > t.candela[best] ? i : best;
  const double peak_c = t.c_deg[best / t.gammas()], peak_g = t.gamma_deg[best % t.gammas()];
  EXPECT_NEAR(peak_c, 296.3, 5.0);
  EXPECT_NEAR(peak_g, 11.2, 2.0);

  const double flux = t.LuminousFlux(), expected = AnalyticFlux(10);
  std::printf("[ measured ] type B flood flux %.1f lm, analytic %.1f lm (%.3f %%)\n", flux, expected,
              100 * (flux / expected - 1));
  EXPECT_NEAR(flux / expected, 1.0, 0.01);
}

TEST(TypeBPhotometry, HalfRangeFileIsMirroredLeftToRight) {
  const PhotometricTable t = ParseIes(TypeBFloodIes(true), "flood_sym.ies");
  double worst = 0, mirror = 0;
  for (double c = 0; c < 360; c += 7.3) {
    for (double g = 0; g < 90; g += 3.1) {
      double h = 0, v = 0;
      TypeBAngles(c, g, &h, &v);
      worst = std::max(worst, std::fabs(t.Evaluate(c, g) - AnalyticTypeBFlood(h, v, 0)));
      mirror = std::max(mirror, std::fabs(t.Evaluate(c, g) - t.Evaluate(360 - c, g)));
    }
  }
  EXPECT_LE(worst, 0.03 * 2000);
  EXPECT_LE(mirror, 1e-9 * 2000);
  EXPECT_NEAR(t.LuminousFlux() / AnalyticFlux(0), 1.0, 0.01);
}

TEST(TypeBPhotometry, TypeBAnglesOutOfRangeAreRejectedWithTheLine) {
  std::string text = TypeBFloodIes(false);
  // The first vertical angle, -90, on line 8 (after the header, TILT and two parameter lines).
  const size_t at = text.find("\n-90 ");
  ASSERT_NE(at, std::string::npos);
  text.replace(at + 1, 3, "-95");
  try {
    ParseIes(text, "bad_flood.ies");
    FAIL() << "expected an error";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad_flood.ies"), std::string::npos) << what;
    EXPECT_NE(what.find("vertical angle 1 is -95"), std::string::npos) << what;
    EXPECT_NE(what.find("[-90, 90]"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace relight::baker
