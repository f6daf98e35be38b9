// Fixed-point SH, A_lm and sigma (runtime/engine/src/sh_eval.cc) against the
// baker's float64 photometry, errors in LSB of the output format.
#include "relight/engine/sh_eval.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "relight/baker/photometry.h"
#include "relight/base/fixed_math.h"

namespace relight {
namespace {

using baker::Vec3;

constexpr double kQ30 = 1073741824.0;
constexpr double kPi = 3.14159265358979323846;

double Real(int64_t v) { return static_cast<double>(v); }

// Random unit directions in Q1.30 (through NormaliseQ30), plus poles, axes
// and near-pole directions where the Cartesian form's q_l^m is largest.
std::vector<std::array<int32_t, 3>> TestDirections() {
  std::vector<std::array<int32_t, 3>> dirs = {
      {0, 0, 1 << 30},    {0, 0, -(1 << 30)}, {1 << 30, 0, 0},       {0, 1 << 30, 0},
      {-(1 << 30), 0, 0}, {0, -(1 << 30), 0}, {3, -2, (1 << 30) - 1}};
  std::mt19937_64 rng(17);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 300; ++i) {
    const double scale = (i % 10 == 0) ? 1e-4 : 1.0;  // some close to +-z
    int64_t v[3] = {static_cast<int64_t>(normal(rng) * scale * 1e15),
                    static_cast<int64_t>(normal(rng) * scale * 1e15),
                    static_cast<int64_t>((i % 2 ? 1e15 : -1e15) * (scale < 1 ? 1.0 : normal(rng)))};
    if (v[0] == 0 && v[1] == 0 && v[2] == 0) continue;
    std::array<int32_t, 3> d;
    NormaliseQ30(v, d.data());
    dirs.push_back(d);
  }
  return dirs;
}

Vec3 ToDouble(const std::array<int32_t, 3>& d) { return {d[0] / kQ30, d[1] / kQ30, d[2] / kQ30}; }

ShTables MakeTables() {
  ShTables t;
  InitShTables(&t);
  return t;
}

TEST(ShTablesQ60, SeedsMatchTheClosedForm) {
  const ShTables t = MakeTables();
  // q_0^0 = 1/sqrt(4 pi); q_1^1 = -sqrt(3/(4 pi)) (sqrt(2) K_11 P_1^1 / sin)
  EXPECT_NEAR(Real(t.seed_q60[0]) / std::ldexp(1.0, 60), 0.5 / std::sqrt(kPi), 1e-15);
  EXPECT_NEAR(Real(t.seed_q60[1]) / std::ldexp(1.0, 60), -std::sqrt(3 / (4 * kPi)), 1e-15);
  EXPECT_NEAR(Real(t.a_q60[16][15]) / std::ldexp(1.0, 60), std::sqrt(33.0), 1e-15);
  // a_l0 = sqrt((4 l^2 - 1) / l^2): from degree 17 on its denominator passes
  // 256, where the Q60 ratio once overflowed.
  const double l = kMaxShDegree;
  EXPECT_NEAR(Real(t.a_q60[kMaxShDegree][0]) / std::ldexp(1.0, 60), std::sqrt((4 * l * l - 1) / (l * l)), 1e-15);
  EXPECT_NEAR(Real(t.a_q60[kMaxShDegree][kMaxShDegree - 1]) / std::ldexp(1.0, 60), std::sqrt(2 * l + 1), 1e-15);
  EXPECT_NEAR(Real(t.four_pi_over_q58[0]) / std::ldexp(1.0, 58), 4 * kPi, 1e-14);
}

TEST(EvalShQ30, WithinOneLsbOfFloat64AtEveryDegree) {
  const ShTables tables = MakeTables();
  std::vector<int32_t> fixed(ShTermCount(kMaxShDegree));
  std::vector<double> ref(ShTermCount(kMaxShDegree));
  std::vector<double> worst_by_degree(kMaxShDegree + 1, 0.0);
  for (const auto& d : TestDirections()) {
    EvalShQ30(tables, kMaxShDegree, d.data(), fixed.data());
    // Reference on the same quantised vector: both sides evaluate the same
    // polynomials, so the difference is the fixed-point arithmetic alone.
    baker::EvalShBasis(kMaxShDegree, ToDouble(d), ref.data());
    for (int t = 0; t < ShTermCount(kMaxShDegree); ++t) {
      const double err = std::abs(fixed[t] - ref[t] * kQ30);
      const int l = ShDegreeOf(t);
      worst_by_degree[l] = std::max(worst_by_degree[l], err);
      ASSERT_LE(err, 1.0) << "t=" << t << " dir=" << d[0] << "," << d[1] << "," << d[2];
    }
  }
  std::cout << "[ measured ] EvalShQ30 max error (LSB of Q1.30) by degree:";
  for (int l = 0; l <= kMaxShDegree; ++l) std::cout << " " << worst_by_degree[l];
  std::cout << "\n";
}

TEST(EvalShQ30, LowerDegreeIsAPrefix) {
  const ShTables tables = MakeTables();
  const auto dirs = TestDirections();
  std::vector<int32_t> full(ShTermCount(kMaxShDegree)), part(ShTermCount(3) + 1, -7);
  EvalShQ30(tables, kMaxShDegree, dirs[20].data(), full.data());
  EvalShQ30(tables, 3, dirs[20].data(), part.data());
  for (int t = 0; t < ShTermCount(3); ++t) EXPECT_EQ(part[t], full[t]);
  EXPECT_EQ(part[ShTermCount(3)], -7);  // writes nothing past (N+1)^2
}

TEST(AimCoefficientsQ30, WithinOneLsbOfFloat64) {
  const ShTables tables = MakeTables();
  std::vector<int64_t> fixed(ShTermCount(kMaxShDegree));
  std::vector<double> ref(ShTermCount(kMaxShDegree));
  double worst = 0.0;
  for (const auto& d : TestDirections()) {
    AimCoefficientsQ30(tables, kMaxShDegree, d.data(), fixed.data());
    baker::AimCoefficients(kMaxShDegree, ToDouble(d), ref.data());
    for (int t = 0; t < ShTermCount(kMaxShDegree); ++t) {
      const double err = std::abs(static_cast<double>(fixed[t]) - ref[t] * kQ30);
      worst = std::max(worst, err);
      ASSERT_LE(err, 1.0) << "t=" << t;
    }
  }
  std::cout << "[ measured ] AimCoefficientsQ30 max error " << worst << " LSB of Q34.30\n";
}

TEST(SigmaQ30, WithinHalfLsbOfFloat64) {
  double worst = 0.0;
  for (int n = 0; n <= kMaxShDegree; ++n) {
    EXPECT_EQ(SigmaQ30(n, 0).raw(), 1 << 30);
    for (int l = 1; l <= n; ++l) {
      const double err = std::abs(SigmaQ30(n, l).raw() - baker::SigmaFactor(n, l) * kQ30);
      worst = std::max(worst, err);
      EXPECT_LE(err, 0.5 + 1e-6) << "N=" << n << " l=" << l;
    }
  }
  // sin(pi)/pi = 0 at l = N+1, the first zero of Eq. 13.
  EXPECT_LE(std::abs(SigmaQ30(7, 8).raw()), 1);
  std::cout << "[ measured ] SigmaQ30 max error " << worst << " LSB of Q1.30\n";
}

}  // namespace
}  // namespace relight
