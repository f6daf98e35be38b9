// The exact direct term: LID lookup (lid_lookup.h) and illuminance
// (direct.h) against float64, plus closed forms (inverse square, Lambert).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "direct.h"
#include "engine_test_support.h"
#include "lid_lookup.h"
#include "relight/baker/photometry.h"
#include "relight/base/fixed_math.h"
#include "weights.h"

namespace relight {
namespace {

using baker::MountingKind;
using testing::Vec3;

constexpr double kTwo32 = 4294967296.0;

Bam GammaToBam(double gamma_deg) {
  return static_cast<Bam>(std::llround(gamma_deg / 360.0 * kTwo32) & 0xffffffffLL);
}

TEST(LidLookup, MatchesFloatLinearInterpolation) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> cd(0.0, 5000.0);
  std::uniform_real_distribution<double> angle(0.0, 180.0);
  for (int M : {2, 7, 180, 360}) {
    std::vector<double> samples(M + 1);
    for (double& s : samples) s = cd(rng);
    const std::vector<int64_t> q16 = testing::ToQ16(samples);
    const std::vector<double> exact = testing::FromQ16(q16);
    double max_step = 0;
    for (int i = 0; i < M; ++i) max_step = std::max(max_step, std::fabs(exact[i + 1] - exact[i]));
    // Position rounded to 2^-16 of a step, result rounded to Q16.
    const double tol = max_step * std::ldexp(1.0, -16) + std::ldexp(1.0, -15);
    double max_err = 0;
    for (int i = 0; i < 20000; ++i) {
      const Bam g = GammaToBam(angle(rng));
      const double ref = testing::LinearLid(exact, g / kTwo32 * 360.0);
      max_err = std::max(max_err, std::fabs(static_cast<double>(LidIntensityQ16(q16.data(), M, g)) / 65536.0 - ref));
    }
    std::printf("  LID M=%d: max |fixed - float| %.2e cd (tolerance %.2e)\n", M, max_err, tol);
    EXPECT_LE(max_err, tol);
    // Samples themselves are exact; past 180 degrees the cone folds back.
    EXPECT_EQ(LidIntensityQ16(q16.data(), M, 0), q16[0]);
    EXPECT_EQ(LidIntensityQ16(q16.data(), M, Bam{1} << 31), q16[M]);
    EXPECT_EQ(LidIntensityQ16(q16.data(), M, GammaToBam(180.0 / M)), q16[1]);
    EXPECT_EQ(LidIntensityQ16(q16.data(), M, GammaToBam(360.0 - 180.0 / M)), q16[1]);
    EXPECT_EQ(LidIntensityQ16(q16.data(), M, GammaToBam(180.0 + 180.0 / M)), q16[M - 1]);
  }
}

TEST(Direct, InverseSquareAndLambertClosedForms) {
  // Isotropic 100 cd, receiver d metres straight along the axis, facing it:
  // E = I / d^2, and a Lambertian vertex of reflectance rho shows rho E / pi.
  const std::vector<int64_t> lid = testing::ToQ16(std::vector<double>(5, 100.0));
  int32_t axis[3];
  BeamAxisQ30(Mounting::kHanging, Q16_16::FromInt(0), Q16_16::FromInt(0), axis);
  for (double d : {0.5, 1.0, 2.0, 3.7}) {
    std::vector<uint32_t> g;
    const QuantScale gs = testing::QuantiseUint32({1.0 / (d * d)}, &g);
    const int16_t dir[3] = {0, 0, -16384};
    const double e_ref = 100.0 / (d * d);
    const double e =
        static_cast<double>(DirectIlluminanceQ20(dir, g[0], gs, axis, lid.data(), 4)) / 1048576.0;
    EXPECT_NEAR(e, e_ref, 1e-6 * e_ref);
    const uint16_t albedo[3] = {65535, 32768, 0};
    uint32_t rho_pi[3];
    ReflectanceOverPiQ32(albedo, 3, rho_pi);
    DirectReceivers rx;
    rx.direction_q14 = dir;
    rx.geometry = g.data();
    rx.geometry_scale = gs;
    rx.count = 1;
    int32_t vertex[3], grid[3];
    DirectLightQ12(rx, axis, lid.data(), 4, rho_pi, DirectStore::kWrite, vertex);
    DirectLightQ12(rx, axis, lid.data(), 4, nullptr, DirectStore::kWrite, grid);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(grid[c] / 4096.0, e_ref, 1.0 / 4096);
      EXPECT_NEAR(vertex[c] / 4096.0, albedo[c] / 65535.0 * e_ref / testing::kPi, 1.0 / 4096);
    }
    // Add mode accumulates, saturating.
    int32_t acc[3] = {1000, 0, 2147483000};
    DirectLightQ12(rx, axis, lid.data(), 4, nullptr, DirectStore::kAdd, acc);
    EXPECT_EQ(acc[0], 1000 + grid[0]);
    EXPECT_EQ(acc[1], grid[1]);
    EXPECT_EQ(acc[2], 2147483647);
  }
}

TEST(Direct, IlluminanceMatchesFloatForManyDirectionsAndAims) {
  constexpr int kM = 180;
  const std::vector<int64_t> lid = testing::ToQ16(testing::CosPowerSamples(1000.0, 10.0, kM));
  const std::vector<double> samples = testing::FromQ16(lid);
  std::mt19937 rng(2024);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> g_real(0.01, 4.0);
  constexpr int kCount = 4000;
  // Directions cluster round the axis (where the beam is) and spread everywhere.
  struct Aim {
    double pan, tilt;
  };
  double worst_data = 0, worst_unquantised = 0;
  for (const Aim& aim : {Aim{0, 0}, Aim{45, 30}, Aim{-120, 80}, Aim{10, 150}}) {
    const Vec3 axis_f = baker::BeamAxis(MountingKind::kHanging, aim.pan, aim.tilt);
    int32_t axis[3];
    BeamAxisQ30(Mounting::kHanging, Q16_16::FromRatio(std::llround(aim.pan * 1000), 1000),
                Q16_16::FromRatio(std::llround(aim.tilt * 1000), 1000), axis);
    std::vector<Vec3> dirs(kCount);
    std::vector<double> g(kCount);
    for (int i = 0; i < kCount; ++i) {
      const double spread = i % 2 ? 0.3 : 3.0;
      dirs[i] = testing::Normalised({axis_f[0] + spread * n(rng), axis_f[1] + spread * n(rng),
                                     axis_f[2] + spread * n(rng)});
      g[i] = g_real(rng);
    }
    std::vector<uint32_t> gq;
    const QuantScale gs = testing::QuantiseUint32(g, &gq);
    double peak = 0, max_err = 0, max_err_unq = 0;
    for (int i = 0; i < kCount; ++i) {
      int16_t dq[3];
      Vec3 dq_f;
      for (int j = 0; j < 3; ++j) {
        dq[j] = static_cast<int16_t>(std::lround(dirs[i][j] * 16384.0));
        dq_f[j] = dq[j] / 16384.0;
      }
      const double g_deq = gq[i] * testing::ScaleValue(gs);
      // Reference on the stored data (Q1.14 direction, quantised G) ...
      const double ref = testing::LinearLid(samples, testing::AngleDeg(dq_f, axis_f)) * g_deq;
      // ... and on the unquantised geometry, for the record.
      const double ref_unq = testing::LinearLid(samples, testing::AngleDeg(dirs[i], axis_f)) * g[i];
      const double e =
          static_cast<double>(DirectIlluminanceQ20(dq, gq[i], gs, axis, lid.data(), kM)) / 1048576.0;
      peak = std::max(peak, ref);
      max_err = std::max(max_err, std::fabs(e - ref));
      max_err_unq = std::max(max_err_unq, std::fabs(e - ref_unq));
    }
    std::printf("  aim pan %.0f tilt %.0f: peak %.1f lux, max |fixed - float| %.2e of peak "
                "(vs unquantised geometry %.2e)\n",
                aim.pan, aim.tilt, peak, max_err / peak, max_err_unq / peak);
    ASSERT_GT(peak, 1000.0);
    EXPECT_LE(max_err, 1e-4 * peak);
    worst_data = std::max(worst_data, max_err / peak);
    worst_unquantised = std::max(worst_unquantised, max_err_unq / peak);
  }
  std::printf("Direct E = I G: worst %.2e of peak on the stored data (bar 1e-4), %.2e vs "
              "unquantised directions/G\n",
              worst_data, worst_unquantised);
}

}  // namespace
}  // namespace relight
