// Fixed-point Legendre weights (runtime/engine/src/legendre_weights.cc, Dobashi
// Eq. 19-21) against the baker's float64 LegendreWeights.
#include "relight/engine/legendre_weights.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "relight/baker/photometry.h"
#include "relight/base/sh_index.h"

namespace relight {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kQ30 = 1073741824.0;
constexpr double kQ16 = 65536.0;

double Real(int64_t v) { return static_cast<double>(v); }

std::vector<int32_t> Table(int degree, int M) {
  std::vector<int32_t> table((degree + 1) * (M + 1));
  const Status st = BuildLegendreTableQ30(degree, M, table.data());
  EXPECT_TRUE(st.ok()) << st.ToString();
  return table;
}

// Candela samples in Q48.16; the float64 reference gets exactly these values.
std::vector<int64_t> ToQ16(const std::vector<double>& cd) {
  std::vector<int64_t> q(cd.size());
  for (size_t i = 0; i < cd.size(); ++i) q[i] = std::llround(cd[i] * kQ16);
  return q;
}
std::vector<double> FromQ16(const std::vector<int64_t>& q) {
  std::vector<double> cd(q.size());
  for (size_t i = 0; i < q.size(); ++i) cd[i] = Real(q[i]) / kQ16;
  return cd;
}

std::vector<double> CosPower(double peak_cd, double k, double spread_deg, int M) {
  std::vector<double> s(M + 1);
  for (int i = 0; i <= M; ++i) {
    const double gamma_deg = 180.0 * i / M;
    s[i] = gamma_deg < spread_deg ? peak_cd * std::pow(std::cos(gamma_deg * kPi / 180), k) : 0.0;
  }
  return s;
}

// A measured-style table beam: linear between control points, 0 past the last.
std::vector<double> TableBeam(int M) {
  const double gamma[] = {0, 5, 10, 20, 30, 45, 60, 75};
  const double cd[] = {800, 790, 720, 500, 260, 80, 15, 0};
  std::vector<double> s(M + 1, 0.0);
  for (int i = 0; i <= M; ++i) {
    const double g = 180.0 * i / M;
    for (int j = 0; j + 1 < 8; ++j) {
      if (g >= gamma[j] && g <= gamma[j + 1]) {
        const double f = (g - gamma[j]) / (gamma[j + 1] - gamma[j]);
        s[i] = cd[j] + f * (cd[j + 1] - cd[j]);
        break;
      }
    }
  }
  return s;
}

TEST(LegendreTableQ30, RejectsBadArguments) {
  std::vector<int32_t> table(17 * 100);
  EXPECT_EQ(BuildLegendreTableQ30(4, 1, table.data()).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(BuildLegendreTableQ30(-1, 10, table.data()).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(BuildLegendreTableQ30(kMaxShDegree + 1, 10, table.data()).code(),
            StatusCode::kInvalidArgument);
  EXPECT_TRUE(BuildLegendreTableQ30(0, 2, table.data()).ok());
}

TEST(LegendreTableQ30, WithinHalfLsbOfEq20) {
  double worst = 0.0;
  for (int M : {2, 3, 8, 11, 90, 180, 361}) {
    const std::vector<int32_t> table = Table(kMaxShDegree, M);
    for (int l = 0; l <= kMaxShDegree; ++l) {
      for (int k = 0; k <= M; ++k) {
        const double gamma = kPi * k / M;
        const double ref = baker::LegendreP(l, std::cos(gamma)) * std::sin(gamma);
        const double err = std::abs(table[l * (M + 1) + k] - ref * kQ30);
        worst = std::max(worst, err);
        ASSERT_LE(err, 0.5 + 1e-3) << "M=" << M << " l=" << l << " k=" << k;
      }
    }
    // sin(0) = sin(pi) = 0: the end samples never contribute.
    for (int l = 0; l <= kMaxShDegree; ++l) {
      EXPECT_EQ(table[l * (M + 1)], 0);
      EXPECT_EQ(table[l * (M + 1) + M], 0);
    }
  }
  std::cout << "[ measured ] Legendre table max error " << worst << " LSB of Q1.30\n";
}

// Relative error |w_fixed - w_float| / w_0 over all l for one beam.
double WeightError(const std::vector<double>& cd, int degree) {
  const int M = static_cast<int>(cd.size()) - 1;
  const std::vector<int64_t> q = ToQ16(cd);
  const std::vector<int32_t> table = Table(degree, M);
  std::vector<int64_t> w(degree + 1);
  LegendreWeightsQ16(table.data(), degree, M, q.data(), w.data());
  const std::vector<double> ref = baker::LegendreWeights(FromQ16(q), degree);
  double worst = 0.0;
  for (int l = 0; l <= degree; ++l)
    worst = std::max(worst, std::abs(Real(w[l]) / kQ16 - ref[l]) / ref[0]);
  return worst;
}

TEST(LegendreWeightsQ16, MatchFloat64WithinOnePpmOfW0) {
  struct Beam {
    const char* name;
    std::vector<double> cd;
  };
  std::vector<Beam> beams;
  for (int M : {90, 180, 361}) {
    beams.push_back({"isotropic 1000 cd", std::vector<double>(M + 1, 1000.0)});
    beams.push_back({"cos^1 2500 cd", CosPower(2500, 1, 90, M)});
    beams.push_back({"cos^10 spread 90, 5000 cd", CosPower(5000, 10, 90, M)});
    beams.push_back({"cos^50 spread 40, 20000 cd", CosPower(20000, 50, 40, M)});
    beams.push_back({"table 800 cd", TableBeam(M)});
  }
  double worst = 0.0;
  for (const Beam& b : beams) {
    for (int degree : {0, 3, 8, 16}) {
      const double err = WeightError(b.cd, degree);
      worst = std::max(worst, err);
      EXPECT_LE(err, 1e-6) << b.name << " M=" << b.cd.size() - 1 << " N=" << degree;
    }
  }
  std::cout << "[ measured ] LegendreWeightsQ16 max |w_l - w_l(float64)| / w_0 = " << worst << "\n";
}

TEST(LegendreWeightsQ16, Eq21UpdateTracksFullRecompute) {
  constexpr int kDegree = 12, M = 90;
  const std::vector<int32_t> table = Table(kDegree, M);
  std::vector<int64_t> q = ToQ16(CosPower(3000, 4, 70, M));
  std::vector<int64_t> w(kDegree + 1), full(kDegree + 1);
  LegendreWeightsQ16(table.data(), kDegree, M, q.data(), w.data());
  std::vector<double> w_float = baker::LegendreWeights(FromQ16(q), kDegree);
  std::mt19937_64 rng(9);
  std::vector<int> ks = {0, M, 1, M - 1};  // ends carry t_k = 1/2
  for (int i = 0; i < 60; ++i) ks.push_back(static_cast<int>(rng() % (M + 1)));
  for (int k : ks) {
    const int64_t new_q = static_cast<int64_t>(rng() % (4000u << 16));
    UpdateLegendreWeightsQ16(table.data(), kDegree, M, k, q[k], new_q, w.data());
    baker::UpdateLegendreWeights(&w_float, M, k, Real(q[k]) / kQ16, Real(new_q) / kQ16);
    q[k] = new_q;
  }
  LegendreWeightsQ16(table.data(), kDegree, M, q.data(), full.data());
  // Each update rounds once (<= 0.5 LSB) and the full sum rounds once.
  const double bound_lsb = 0.5 * static_cast<double>(ks.size()) + 0.5;
  int64_t worst = 0;
  for (int l = 0; l <= kDegree; ++l) {
    worst = std::max(worst, std::abs(w[l] - full[l]));
    EXPECT_LE(static_cast<double>(std::abs(w[l] - full[l])), bound_lsb) << "l=" << l;
    EXPECT_NEAR(Real(w[l]) / kQ16, w_float[l], 1e-6 * w_float[0]) << "l=" << l;
  }
  std::cout << "[ measured ] Eq. 21 fixed: " << ks.size() << " updates drift at most " << worst
            << " LSB of Q48.16 from a full recompute (bound " << bound_lsb << ")\n";
}

TEST(LegendreWeightsQ16, UpdateOfAnUnchangedSampleIsANoOp) {
  constexpr int kDegree = 8, M = 11;
  const std::vector<int32_t> table = Table(kDegree, M);
  const std::vector<int64_t> q = ToQ16(CosPower(100, 2, 90, M));
  std::vector<int64_t> w(kDegree + 1), before;
  LegendreWeightsQ16(table.data(), kDegree, M, q.data(), w.data());
  before = w;
  for (int k = 0; k <= M; ++k)
    UpdateLegendreWeightsQ16(table.data(), kDegree, M, k, q[k], q[k], w.data());
  EXPECT_EQ(w, before);
}

}  // namespace
}  // namespace relight
