// Float64 photometry (baker/src/photometry.cc) against closed forms:
// orthogonality, the addition theorem, Eq. 19 / 21, the sigma factor (Eq. 13)
// and rotation through A_lm (Eq. 10, 18).
#include "relight/baker/photometry.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Gauss-Legendre nodes and weights on [-1, 1] by Golub-Welsch (eigenvalues of
// the Jacobi matrix), independent of the LegendreP under test. Exact for
// polynomials of degree <= 2n-1.
void GaussLegendre(int n, std::vector<double>* nodes, std::vector<double>* weights) {
  Eigen::MatrixXd jacobi = Eigen::MatrixXd::Zero(n, n);
  for (int k = 1; k < n; ++k) {
    const double beta = k / std::sqrt(4.0 * k * k - 1.0);
    jacobi(k - 1, k) = beta;
    jacobi(k, k - 1) = beta;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(jacobi);
  nodes->resize(n);
  weights->resize(n);
  for (int i = 0; i < n; ++i) {
    (*nodes)[i] = solver.eigenvalues()(i);
    const double v0 = solver.eigenvectors()(0, i);
    (*weights)[i] = 2.0 * v0 * v0;
  }
}

Vec3 RandomUnit(std::mt19937_64* rng) {
  std::normal_distribution<double> normal;
  for (;;) {
    Vec3 v{normal(*rng), normal(*rng), normal(*rng)};
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 1e-6) return {v[0] / n, v[1] / n, v[2] / n};
  }
}

double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// cos^k(gamma) for gamma < spread, 0 beyond (Dobashi Eq. 11), M+1 samples.
std::vector<double> CosPowerSamples(double peak_cd, double k, double spread_deg, int M) {
  std::vector<double> s(M + 1);
  for (int i = 0; i <= M; ++i) {
    const double gamma = kPi * i / M;
    s[i] = gamma < spread_deg * kPi / 180.0 ? peak_cd * std::pow(std::cos(gamma), k) : 0.0;
  }
  return s;
}

double LegendreSeries(const std::vector<double>& w, double cos_gamma, bool use_sigma) {
  const int degree = static_cast<int>(w.size()) - 1;
  double sum = 0.0;
  for (int l = 0; l <= degree; ++l) {
    sum += (use_sigma ? SigmaFactor(degree, l) : 1.0) * w[l] * LegendreP(l, cos_gamma);
  }
  return sum;
}

TEST(Legendre, ClosedFormsOfLowDegree) {
  for (double x = -1.0; x <= 1.0; x += 0.125) {
    EXPECT_NEAR(LegendreP(0, x), 1.0, 1e-15);
    EXPECT_NEAR(LegendreP(1, x), x, 1e-15);
    EXPECT_NEAR(LegendreP(2, x), 0.5 * (3 * x * x - 1), 1e-15);
    EXPECT_NEAR(LegendreP(3, x), 0.5 * (5 * x * x * x - 3 * x), 1e-15);
    // Condon-Shortley phase: P_1^1 = -sqrt(1-x^2), P_2^2 = 3 (1-x^2)
    EXPECT_NEAR(AssocLegendreP(1, 1, x), -std::sqrt(1 - x * x), 1e-15);
    EXPECT_NEAR(AssocLegendreP(2, 1, x), -3 * x * std::sqrt(1 - x * x), 1e-14);
    EXPECT_NEAR(AssocLegendreP(2, 2, x), 3 * (1 - x * x), 1e-14);
    EXPECT_NEAR(AssocLegendreP(5, 0, x), LegendreP(5, x), 1e-14);
  }
  for (int l = 0; l <= 16; ++l) {
    EXPECT_NEAR(LegendreP(l, 1.0), 1.0, 1e-14);
    EXPECT_NEAR(LegendreP(l, -1.0), (l % 2 == 0) ? 1.0 : -1.0, 1e-14);
  }
}

TEST(Legendre, OrthogonalOnMinusOneToOne) {
  std::vector<double> x, wq;
  GaussLegendre(24, &x, &wq);  // exact up to degree 47 >= 32
  for (int l = 0; l <= 16; ++l) {
    for (int k = 0; k <= 16; ++k) {
      double integral = 0.0;
      for (size_t i = 0; i < x.size(); ++i)
        integral += wq[i] * LegendreP(l, x[i]) * LegendreP(k, x[i]);
      const double expected = (l == k) ? 2.0 / (2 * l + 1) : 0.0;
      EXPECT_NEAR(integral, expected, 1e-13) << "l=" << l << " k=" << k;
    }
  }
}

TEST(ShBasis, ClosedFormsFixTheConvention) {
  // Real SH with the Condon-Shortley phase (sh_index.h).
  std::mt19937_64 rng(7);
  for (int i = 0; i < 50; ++i) {
    const Vec3 d = RandomUnit(&rng);
    const double x = d[0], y = d[1], z = d[2];
    EXPECT_NEAR(ShY(0, 0, d), 0.5 * std::sqrt(1 / kPi), 1e-15);
    EXPECT_NEAR(ShY(1, -1, d), -std::sqrt(3 / (4 * kPi)) * y, 1e-15);
    EXPECT_NEAR(ShY(1, 0, d), std::sqrt(3 / (4 * kPi)) * z, 1e-15);
    EXPECT_NEAR(ShY(1, 1, d), -std::sqrt(3 / (4 * kPi)) * x, 1e-15);
    EXPECT_NEAR(ShY(2, -2, d), 0.5 * std::sqrt(15 / kPi) * x * y, 1e-14);
    EXPECT_NEAR(ShY(2, -1, d), -0.5 * std::sqrt(15 / kPi) * y * z, 1e-14);
    EXPECT_NEAR(ShY(2, 0, d), 0.25 * std::sqrt(5 / kPi) * (3 * z * z - 1), 1e-14);
    EXPECT_NEAR(ShY(2, 1, d), -0.5 * std::sqrt(15 / kPi) * x * z, 1e-14);
    EXPECT_NEAR(ShY(2, 2, d), 0.25 * std::sqrt(15 / kPi) * (x * x - y * y), 1e-14);
  }
}

double Factorial(int n) {
  double f = 1.0;
  for (int i = 2; i <= n; ++i) f *= i;
  return f;
}

TEST(ShBasis, MatchesSphericalFormWithAssocLegendre) {
  // Y_lm = sqrt(2) K_lm P_l^m(cos theta) {cos, sin}(|m| phi): the angle form of
  // sh_index.h, against the Cartesian recurrence in photometry.cc.
  std::mt19937_64 rng(11);
  std::vector<double> basis(ShTermCount(16));
  for (int i = 0; i < 40; ++i) {
    const Vec3 d = RandomUnit(&rng);
    const double theta = std::acos(d[2]), phi = std::atan2(d[1], d[0]);
    EvalShBasis(16, d, basis.data());
    for (int l = 0; l <= 16; ++l) {
      for (int m = -l; m <= l; ++m) {
        const int am = std::abs(m);
        const double k_lm =
            std::sqrt((2 * l + 1) / (4 * kPi) * Factorial(l - am) / Factorial(l + am));
        double expected = k_lm * AssocLegendreP(l, am, std::cos(theta));
        if (m > 0) expected *= std::sqrt(2.0) * std::cos(am * phi);
        if (m < 0) expected *= std::sqrt(2.0) * std::sin(am * phi);
        EXPECT_NEAR(basis[ShIndex(l, m)], expected, 1e-11) << "l=" << l << " m=" << m;
        EXPECT_NEAR(ShY(l, m, d), basis[ShIndex(l, m)], 1e-15);
      }
    }
  }
}

TEST(ShBasis, OrthonormalOnTheSphere) {
  constexpr int kDegree = 8;
  constexpr int kTerms = ShTermCount(kDegree);
  // Gauss-Legendre in z (exact to degree 23 >= 16) x uniform in phi (exact for
  // trig degree < 34 >= 16).
  std::vector<double> z, wz;
  GaussLegendre(12, &z, &wz);
  constexpr int kPhi = 34;
  std::vector<double> gram(kTerms * kTerms, 0.0), y(kTerms);
  for (size_t i = 0; i < z.size(); ++i) {
    const double r = std::sqrt(1 - z[i] * z[i]);
    for (int j = 0; j < kPhi; ++j) {
      const double phi = 2 * kPi * j / kPhi;
      EvalShBasis(kDegree, {r * std::cos(phi), r * std::sin(phi), z[i]}, y.data());
      const double w = wz[i] * 2 * kPi / kPhi;
      for (int a = 0; a < kTerms; ++a)
        for (int b = 0; b < kTerms; ++b) gram[a * kTerms + b] += w * y[a] * y[b];
    }
  }
  double worst = 0.0;
  for (int a = 0; a < kTerms; ++a)
    for (int b = 0; b < kTerms; ++b)
      worst = std::max(worst, std::abs(gram[a * kTerms + b] - (a == b ? 1.0 : 0.0)));
  EXPECT_LT(worst, 1e-13);
}

TEST(ShBasis, AdditionTheorem) {
  // Dobashi Eq. 7: P_l(a.b) = 4 pi/(2l+1) sum_m Y_lm(a) Y_lm(b)
  std::mt19937_64 rng(3);
  std::vector<double> ya(ShTermCount(16)), yb(ShTermCount(16));
  double worst = 0.0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 a = RandomUnit(&rng), b = RandomUnit(&rng);
    EvalShBasis(16, a, ya.data());
    EvalShBasis(16, b, yb.data());
    for (int l = 0; l <= 16; ++l) {
      double sum = 0.0;
      for (int m = -l; m <= l; ++m) sum += ya[ShIndex(l, m)] * yb[ShIndex(l, m)];
      const double err = std::abs(4 * kPi / (2 * l + 1) * sum - LegendreP(l, Dot(a, b)));
      worst = std::max(worst, err);
    }
  }
  EXPECT_LT(worst, 1e-10);
  // At the poles too (Cartesian form: no singularity).
  EvalShBasis(16, {0, 0, 1}, ya.data());
  EvalShBasis(16, {0, 0, -1}, yb.data());
  for (int l = 0; l <= 16; ++l) {
    double sum = 0.0;
    for (int m = -l; m <= l; ++m) sum += ya[ShIndex(l, m)] * yb[ShIndex(l, m)];
    EXPECT_NEAR(4 * kPi / (2 * l + 1) * sum, (l % 2 == 0) ? 1.0 : -1.0, 1e-10);
  }
}

// The trapezoid rule of Eq. 19 errs by (h^2/12) (g'(pi) - g'(0)) + O(h^4) for
// g = I(gamma) P_l(cos gamma) sin gamma; tolerances below come from that term.
TEST(LegendreWeightsEq19, IsotropicGivesOnlyW0) {
  constexpr double kCd = 750.0;
  constexpr int M = 180;
  const double h = kPi / M;
  const std::vector<double> w = LegendreWeights(std::vector<double>(M + 1, kCd), 16);
  ASSERT_EQ(w.size(), 17u);
  // g'(0) = 1, g'(pi) = -1 for even l: w_l error ~ -(2l+1)/2 c h^2/6.
  EXPECT_NEAR(w[0], kCd, 1.01 * kCd * h * h / 12);
  // Closed form of the trapezoid sum itself: (c/2) h cot(h/2).
  EXPECT_NEAR(w[0], kCd / 2 * h / std::tan(h / 2), 1e-10);
  for (int l = 1; l <= 16; ++l) {
    const double bound = (l % 2 == 1) ? 1e-10 : 1.01 * (2 * l + 1) / 2.0 * kCd * h * h / 6;
    EXPECT_LE(std::abs(w[l]), bound) << "l=" << l;
  }
}

TEST(LegendreWeightsEq19, CosineGivesW1) {
  constexpr int M = 360;
  const double h = kPi / M;
  std::vector<double> s(M + 1);
  for (int k = 0; k <= M; ++k) s[k] = std::cos(kPi * k / M);
  const std::vector<double> w = LegendreWeights(s, 8);
  EXPECT_NEAR(w[1], 1.0, 1.01 * h * h / 4);  // 3/2 (2/3 - h^2/6)
  EXPECT_NEAR(w[0], 0.0, 1e-12);             // odd integrand: exact by symmetry
  for (int l = 2; l <= 8; ++l) {
    const double bound = (l % 2 == 0) ? 1e-12 : 1.01 * (2 * l + 1) / 2.0 * h * h / 6;
    EXPECT_LE(std::abs(w[l]), bound) << "l=" << l;
  }
}

TEST(LegendreWeightsEq19, SeriesReconstructsASmoothLid) {
  // I = 400 exp(cos gamma) + 100: Legendre coefficients fall off like 1/l!,
  // so degree 12 is exact to ~1e-9; what remains is the O(h^2) of Eq. 19.
  constexpr int M = 720;
  std::vector<double> s(M + 1);
  auto lid = [](double gamma) { return 400.0 * std::exp(std::cos(gamma)) + 100.0; };
  for (int k = 0; k <= M; ++k) s[k] = lid(kPi * k / M);
  const std::vector<double> w = LegendreWeights(s, 12);
  double worst = 0.0;
  for (int i = 0; i <= 360; ++i) {
    const double gamma = kPi * i / 360;
    worst = std::max(worst, std::abs(LegendreSeries(w, std::cos(gamma), false) - lid(gamma)));
  }
  // Leading trapezoid error of w_l: (2l+1)/2 (h^2/12) |g_l'(pi) - g_l'(0)|, with
  // g_l'(0) = I(0) and |g_l'(pi)| = I(pi); summed over l as |P_l| <= 1.
  const double h = kPi / M;
  double bound = 0.0;
  for (int l = 0; l <= 12; ++l) bound += (2 * l + 1) / 2.0 * h * h / 12 * (lid(0) + lid(kPi));
  const double peak = lid(0);
  std::cout << "[ measured ] smooth LID, N=12, M=720: max reconstruction error " << worst / peak
            << " of peak (Euler-Maclaurin bound " << bound / peak << ")\n";
  EXPECT_LT(worst, 1.1 * bound);
  EXPECT_LT(worst / peak, 2e-4);
}

TEST(LegendreWeightsEq21, IncrementalEqualsFullRecompute) {
  constexpr int M = 90;
  std::vector<double> s = CosPowerSamples(2000.0, 4, 70, M);
  std::vector<double> w = LegendreWeights(s, 16);
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> pick(0, M);
  std::uniform_real_distribution<double> value(0.0, 3000.0);
  std::vector<int> ks = {0, M};  // end points carry t_k = 1/2
  for (int i = 0; i < 40; ++i) ks.push_back(pick(rng));
  for (int k : ks) {
    const double new_cd = value(rng);
    UpdateLegendreWeights(&w, M, k, s[k], new_cd);
    s[k] = new_cd;
  }
  const std::vector<double> full = LegendreWeights(s, 16);
  for (int l = 0; l <= 16; ++l) EXPECT_NEAR(w[l], full[l], 1e-9) << "l=" << l;
}

TEST(LegendreWeightsEq19, SampleLidFollowsTheLid) {
  Lid lid;
  lid.kind = LidKind::kCosPower;
  lid.peak_cd = 1200.0;
  lid.exponent = 3.0;
  lid.spread_deg = 60.0;
  const std::vector<double> s = SampleLid(lid, 36);  // 5 degree steps
  ASSERT_EQ(s.size(), 37u);
  for (int k = 0; k <= 36; ++k) {
    const double gamma_deg = 5.0 * k;
    EXPECT_DOUBLE_EQ(s[k], lid.Evaluate(gamma_deg));
    if (gamma_deg < 59.0) {
      EXPECT_NEAR(s[k], 1200.0 * std::pow(std::cos(gamma_deg * kPi / 180), 3), 1e-9);
    }
    if (gamma_deg > 61.0) {
      EXPECT_EQ(s[k], 0.0);
    }
  }
}

TEST(SigmaFactor, Eq13ClosedForm) {
  for (int n = 0; n <= 16; ++n) {
    EXPECT_EQ(SigmaFactor(n, 0), 1.0);
    for (int l = 1; l <= n; ++l) {
      const double x = kPi * l / (n + 1);
      EXPECT_NEAR(SigmaFactor(n, l), std::sin(x) / x, 1e-15);
      EXPECT_GT(SigmaFactor(n, l), 0.0);
      EXPECT_LT(SigmaFactor(n, l), SigmaFactor(n, l - 1));
    }
  }
}

TEST(SigmaFactor, SuppressesGibbsRipplesOfTheDobashiSpot) {
  // Dobashi Fig. 3: cos^10, 90 degree spread, N = 8.
  constexpr int M = 720;
  const std::vector<double> w = LegendreWeights(CosPowerSamples(1.0, 10, 90, M), 8);
  double min_plain = 0.0, min_sigma = 0.0;
  for (int i = 0; i <= 900; ++i) {
    const double gamma = kPi / 2 + kPi / 2 * i / 900;  // [90, 180] degrees
    min_plain = std::min(min_plain, LegendreSeries(w, std::cos(gamma), false));
    min_sigma = std::min(min_sigma, LegendreSeries(w, std::cos(gamma), true));
  }
  // Peak of the LID itself is 1 cd.
  std::cout << "[ measured ] cos^10 spread 90 N=8: min over [90,180] deg without sigma "
            << 100 * min_plain << "% of peak, with sigma " << 100 * min_sigma << "% of peak\n";
  // Measured (M = 720): -0.29% without sigma, -0.091% with it. cos^10 is
  // already flat at 90 degrees, so the ripple is small; sigma cuts it ~3x.
  EXPECT_LT(min_plain, -0.0025);  // a negative lobe: negative candela
  EXPECT_GT(min_sigma, -0.001);
  EXPECT_LT(std::abs(min_sigma), std::abs(min_plain) / 3);
}

TEST(Rotation, ShIntensityEqualsLegendreSeriesAboutTheAim) {
  constexpr int kDegree = 10;
  const std::vector<double> w = LegendreWeights(CosPowerSamples(5000.0, 6, 80, 360), kDegree);
  std::mt19937_64 rng(19);
  for (bool use_sigma : {false, true}) {
    for (int i = 0; i < 30; ++i) {
      const Vec3 aim = RandomUnit(&rng);
      const std::vector<double> tw = TermWeights(w, aim, use_sigma);
      ASSERT_EQ(tw.size(), static_cast<size_t>(ShTermCount(kDegree)));
      for (int j = 0; j < 20; ++j) {
        const Vec3 d = RandomUnit(&rng);
        EXPECT_NEAR(ShIntensity(kDegree, tw, d), LegendreSeries(w, Dot(aim, d), use_sigma),
                    1e-9 * 5000.0);
      }
      // And on the axis itself.
      EXPECT_NEAR(ShIntensity(kDegree, tw, aim), LegendreSeries(w, 1.0, use_sigma), 1e-9 * 5000.0);
    }
  }
}

TEST(Rotation, AimCoefficientsAreEq10) {
  std::mt19937_64 rng(23);
  std::vector<double> a(ShTermCount(6));
  for (int i = 0; i < 10; ++i) {
    const Vec3 aim = RandomUnit(&rng);
    AimCoefficients(6, aim, a.data());
    for (int l = 0; l <= 6; ++l)
      for (int m = -l; m <= l; ++m)
        EXPECT_NEAR(a[ShIndex(l, m)], 4 * kPi / (2 * l + 1) * ShY(l, m, aim), 1e-14);
  }
}

}  // namespace
}  // namespace relight::baker
