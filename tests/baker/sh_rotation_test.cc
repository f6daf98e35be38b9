// Real-SH rotation (Ivanic-Ruedenberg, float64) against direct evaluation of
// the rotated function, and the SH projection of LIDs against closed forms
// and against the Legendre weights of the axisymmetric path.
#include "relight/baker/sh_rotation.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "relight/baker/fixture_frame.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/photometry.h"
#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 RandomUnit(std::mt19937* rng) {
  std::normal_distribution<double> n(0, 1);
  Vec3 v{n(*rng), n(*rng), n(*rng)};
  const double l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / l, v[1] / l, v[2] / l};
}

// A random rotation from a random fixture pose, as rows of R (world = R local).
void PoseRotation(const FixturePose& pose, double r[3][3]) {
  const FixtureFrame f = MakeFixtureFrame(pose);
  for (int i = 0; i < 3; ++i) {
    r[i][0] = f.c0[i];
    r[i][1] = f.c90[i];
    r[i][2] = -f.axis[i];
  }
}

double Eval(int degree, const std::vector<double>& c, const Vec3& d) {
  std::vector<double> y(ShTermCount(degree));
  EvalShBasis(degree, d, y.data());
  double s = 0;
  for (size_t t = 0; t < y.size(); ++t) s += c[t] * y[t];
  return s;
}

TEST(ShRotation, RotatedCoefficientsEvaluateTheRotatedFunction) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-180, 180), coef(-1, 1);
  for (int degree : {1, 2, 3, 8, 16}) {
    for (int trial = 0; trial < 4; ++trial) {
      const FixturePose pose{static_cast<MountingKind>(trial % 3), angle(rng), angle(rng),
                             angle(rng), angle(rng)};
      double r[3][3];
      PoseRotation(pose, r);
      std::vector<double> c(ShTermCount(degree));
      for (double& v : c) v = coef(rng);
      const std::vector<double> bands = ShRotationMatrices(degree, r);
      const std::vector<double> rotated = RotateSh(degree, bands, c);
      double worst = 0;
      for (int k = 0; k < 50; ++k) {
        const Vec3 d = RandomUnit(&rng);
        // R^T d: the world direction in local coordinates.
        const Vec3 local{r[0][0] * d[0] + r[1][0] * d[1] + r[2][0] * d[2],
                         r[0][1] * d[0] + r[1][1] * d[1] + r[2][1] * d[2],
                         r[0][2] * d[0] + r[1][2] * d[1] + r[2][2] * d[2]};
        worst = std::max(worst, std::abs(Eval(degree, rotated, d) - Eval(degree, c, local)));
      }
      EXPECT_LT(worst, 1e-10 * ShTermCount(degree)) << "degree " << degree;
    }
  }
}

TEST(ShRotation, BandMatricesAreOrthogonal) {
  const FixturePose pose{MountingKind::kWall, 20, 33, -71, 12};
  double r[3][3];
  PoseRotation(pose, r);
  const std::vector<double> bands = ShRotationMatrices(16, r);
  for (int l = 0; l <= 16; ++l) {
    const double* d = bands.data() + ShRotationBandOffset(l);
    const int n = 2 * l + 1;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        double dot = 0;
        for (int k = 0; k < n; ++k) dot += d[i * n + k] * d[j * n + k];
        ASSERT_NEAR(dot, i == j ? 1.0 : 0.0, 1e-12) << l;
      }
    }
  }
}

// An axisymmetric LID projects onto zonal terms, which are the Legendre
// weights: I = sum_l w_l P_l(cos gamma) and, with z = -cos gamma in the
// fixture frame, c_l0 = (-1)^l sqrt(4 pi / (2l+1)) w_l.
TEST(ShProjection, AxisymmetricLidGivesTheLegendreWeights) {
  Lid lid;
  lid.kind = LidKind::kCosPower;
  lid.exponent = 6;
  lid.spread_deg = 90;
  lid.peak_cd = 1000;
  const int degree = 10;
  const std::vector<double> c = ProjectLidSh(lid, degree);
  const std::vector<double> w = LegendreWeights(SampleLid(lid, 1440), degree);
  for (int l = 0; l <= degree; ++l) {
    const double expected = (l % 2 ? -1.0 : 1.0) * std::sqrt(4 * kPi / (2 * l + 1)) * w[l];
    // Two quadratures (trapezoid M = 1440 vs 720 midpoint rings): 1e-4 of w_0.
    EXPECT_NEAR(c[ShIndex(l, 0)], expected, 1e-4 * w[0]) << l;
    for (int m = -l; m <= l; ++m) {
      if (m != 0) {
        EXPECT_NEAR(c[ShIndex(l, m)], 0.0, 1e-9 * w[0]);
      }
    }
  }
}

// A LID that is itself a low-degree SH expansion in the fixture frame
// projects back onto its coefficients (up to the table's interpolation).
TEST(ShProjection, BandLimitedTableProjectsOntoItsCoefficients) {
  const int degree = 3;
  std::vector<double> truth(ShTermCount(degree), 0.0);
  truth[ShIndex(0, 0)] = 500;
  truth[ShIndex(1, -1)] = 120;
  truth[ShIndex(1, 1)] = -80;
  truth[ShIndex(2, 2)] = 60;
  truth[ShIndex(3, -2)] = 40;
  auto table = std::make_shared<PhotometricTable>();
  table->symmetry = CSymmetry::kNone;
  for (int c = 0; c <= 360; c += 1) table->c_deg.push_back(c);
  for (int g = 0; g <= 180; g += 1) table->gamma_deg.push_back(g);
  for (double c : table->c_deg) {
    for (double g : table->gamma_deg) {
      const double cr = c * kPi / 180, gr = g * kPi / 180;
      const Vec3 d{std::sin(gr) * std::cos(cr), std::sin(gr) * std::sin(cr), -std::cos(gr)};
      table->candela.push_back(Eval(degree, truth, d));
    }
  }
  Lid lid;
  lid.kind = LidKind::kCGamma;
  lid.file = table;
  const std::vector<double> c = ProjectLidSh(lid, 5);
  for (int t = 0; t < ShTermCount(5); ++t) {
    const double expected = t < ShTermCount(degree) ? truth[t] : 0.0;
    EXPECT_NEAR(c[t], expected, 0.05) << "term " << t;  // 1-degree bilinear table
  }
}

}  // namespace
}  // namespace relight::baker
