// The aimed direct term (direct_aimed.h): the acos table against float64,
// the 64-bit LID lookup against the 128-bit one, and the whole kernel
// against the full path (direct.h, root + atan2 per receiver) in LSB and
// against float64 on the stored data, for a wide and a narrow beam.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "direct.h"
#include "direct_aimed.h"
#include "engine_test_support.h"
#include "gamma_table.h"
#include "lid_lookup.h"
#include "relight/bake/bake_limits.h"
#include "relight/baker/photometry.h"
#include "weights.h"

namespace relight {
namespace {

using baker::MountingKind;
using testing::Vec3;

constexpr double kTwo32 = 4294967296.0;
constexpr double kTwo60 = 1152921504606846976.0;

TEST(GammaTable, MatchesFloatAcosAcrossTheSphere) {
  const GammaTable& t = SharedGammaTable();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), expo(-40.0, 0.0);
  double worst_bam = 0;
  for (int i = 0; i < 200000; ++i) {
    // Half uniform in cos, half crowded against cos = +-1 (the root ends).
    double c = unit(rng);
    if (i % 2) c = (c < 0 ? -1.0 : 1.0) * (1.0 - std::pow(2.0, expo(rng)));
    const int64_t c_q60 = static_cast<int64_t>(std::llround(c * kTwo60));
    const double exact = std::acos(static_cast<double>(c_q60) / kTwo60) / (2 * M_PI) * kTwo32;
    worst_bam = std::max(worst_bam, std::fabs(static_cast<double>(GammaFromCosQ60(t, c_q60)) - exact));
  }
  std::printf("  acos table: worst %.0f BAM (%.1e degrees)\n", worst_bam, worst_bam / kTwo32 * 360);
  EXPECT_LE(worst_bam, 5000.0);  // a Q1.14 direction is good to ~2e4 BAM
  EXPECT_EQ(GammaFromCosQ60(t, int64_t{1} << 60), 0u);
  EXPECT_EQ(GammaFromCosQ60(t, -(int64_t{1} << 60)), Bam{1} << 31);
  EXPECT_NEAR(static_cast<double>(GammaFromCosQ60(t, 0)), kTwo32 / 4, 2.0);
}

TEST(GammaTable, LidLookupWithoutWideProductsIsTheSame) {
  std::mt19937_64 rng(3);
  for (int M : {1, 7, 180, 720}) {
    std::uniform_int_distribution<int64_t> cd(0, bake_format::kMaxCandelaRaw);
    std::vector<int64_t> lid(M + 1);
    for (int64_t& v : lid) v = cd(rng);
    lid[0] = bake_format::kMaxCandelaRaw;  // steepest possible step
    if (M > 1) lid[1] = 0;
    std::uniform_int_distribution<uint32_t> g(0, uint32_t{1} << 31);
    for (int i = 0; i < 20000; ++i) {
      const Bam gamma = i < 3 ? (Bam{1} << 31) * static_cast<uint32_t>(i) / 2 : g(rng);
      ASSERT_EQ(LidIntensityFastQ16(lid.data(), M, gamma), LidIntensityQ16(lid.data(), M, gamma))
          << "M " << M << " gamma " << gamma;
    }
  }
}

struct Compared {
  double worst_lsb = 0, worst_of_peak = 0, worst_full_of_peak = 0, worst_unquantised_of_peak = 0;
};

// Random receivers round an aim; both kernels into luminance (with rho) and
// the float64 value of I(angle of the stored Q1.14 direction) G rho / pi.
Compared CompareKernels(const std::vector<double>& lid_cd, double pan, double tilt, bool with_rho,
                        std::mt19937* rng) {
  const int M = static_cast<int>(lid_cd.size()) - 1;
  const std::vector<int64_t> lid = testing::ToQ16(lid_cd);
  const std::vector<double> samples = testing::FromQ16(lid);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> g_real(0.01, 4.0);
  const Vec3 axis_f = baker::BeamAxis(MountingKind::kHanging, pan, tilt);
  int32_t axis[3];
  BeamAxisQ30(Mounting::kHanging, Q16_16::FromRatio(std::llround(pan * 1000), 1000),
              Q16_16::FromRatio(std::llround(tilt * 1000), 1000), axis);
  constexpr uint32_t kCount = 6000;
  std::vector<int16_t> dq(kCount * 3);
  std::vector<double> g(kCount);
  std::vector<Vec3> exact_dir(kCount);
  for (uint32_t i = 0; i < kCount; ++i) {
    const double spread = i % 3 == 0 ? 3.0 : (i % 3 == 1 ? 0.2 : 0.02);
    const Vec3 d = testing::Normalised({axis_f[0] + spread * n(*rng), axis_f[1] + spread * n(*rng),
                                        axis_f[2] + spread * n(*rng)});
    exact_dir[i] = d;
    for (int j = 0; j < 3; ++j) dq[i * 3 + j] = static_cast<int16_t>(std::lround(d[j] * 16384.0));
    g[i] = g_real(*rng);
  }
  std::vector<uint32_t> gq;
  const QuantScale gs = testing::QuantiseUint32(g, &gq);
  std::vector<uint16_t> albedo(kCount * 3);
  for (size_t i = 0; i < albedo.size(); ++i) albedo[i] = static_cast<uint16_t>(3000 + 7919 * i % 62000);
  std::vector<uint32_t> rho(kCount * 3);
  ReflectanceOverPiQ32(albedo.data(), kCount * 3, rho.data());
  DirectReceivers rx{dq.data(), gq.data(), gs, kCount};
  DirectPoints points;
  PrepareDirectPoints(rx, &points);
  std::vector<int32_t> full(kCount * 3), aimed(kCount * 3);
  const uint32_t* r = with_rho ? rho.data() : nullptr;
  DirectLightQ12(rx, axis, lid.data(), M, r, DirectStore::kWrite, full.data());
  DirectLightAimedQ12(points, SharedGammaTable(), axis, lid.data(), M, r, DirectStore::kWrite, aimed.data());
  Compared out;
  double peak = 0, max_err = 0, max_err_full = 0, max_err_unq = 0;
  for (uint32_t i = 0; i < kCount; ++i) {
    const Vec3 d = {dq[i * 3] / 16384.0, dq[i * 3 + 1] / 16384.0, dq[i * 3 + 2] / 16384.0};
    const double e = testing::LinearLid(samples, testing::AngleDeg(d, axis_f)) * gq[i] * testing::ScaleValue(gs);
    // What the Q1.14 direction itself is worth: the same on the unrounded one.
    const double e_unq = testing::LinearLid(samples, testing::AngleDeg(exact_dir[i], axis_f)) * gq[i] * testing::ScaleValue(gs);
    for (int c = 0; c < 3; ++c) {
      const double k = (with_rho ? albedo[i * 3 + c] / 65535.0 / M_PI : 1.0) * 4096.0;
      const double ref = e * k;
      max_err_unq = std::max(max_err_unq, std::fabs(e_unq * k - ref));
      peak = std::max(peak, ref);
      max_err = std::max(max_err, std::fabs(aimed[i * 3 + c] - ref));
      max_err_full = std::max(max_err_full, std::fabs(full[i * 3 + c] - ref));
      out.worst_lsb = std::max(out.worst_lsb, std::fabs(static_cast<double>(aimed[i * 3 + c]) - full[i * 3 + c]));
    }
  }
  out.worst_of_peak = max_err / peak;
  out.worst_full_of_peak = max_err_full / peak;
  out.worst_unquantised_of_peak = max_err_unq / peak;
  return out;
}

TEST(DirectAimed, MatchesTheFullPathAndFloat) {
  std::mt19937 rng(2025);
  struct Beam {
    const char* name;
    std::vector<double> cd;
  };
  // A wide cosine lobe and a narrow one (~6 degrees at half peak: where a
  // coarse gamma would show first).
  const Beam beams[] = {{"cos^10", testing::CosPowerSamples(1000.0, 10.0, 180)},
                        {"cos^500", testing::CosPowerSamples(50000.0, 500.0, 720)}};
  struct Aim {
    double pan, tilt;
  };
  for (const Beam& beam : beams) {
    for (const Aim& aim : {Aim{0, 0}, Aim{45, 30}, Aim{-120, 80}, Aim{10, 150}}) {
      for (bool with_rho : {true, false}) {
        const Compared c = CompareKernels(beam.cd, aim.pan, aim.tilt, with_rho, &rng);
        std::printf("  %s pan %.0f tilt %.0f %s: aimed vs full path max %.0f LSB; vs float64 "
                    "%.2e of peak (full path %.2e; the Q1.14 rounding of the direction: %.2e)\n",
                    beam.name, aim.pan, aim.tilt, with_rho ? "luminance" : "lux", c.worst_lsb,
                    c.worst_of_peak, c.worst_full_of_peak, c.worst_unquantised_of_peak);
        // The acos table's ~1e3 BAM: a few 1e-6 of peak, far below what the
        // bake's Q1.14 direction is good to (~1e-4 of peak on these beams).
        EXPECT_LE(c.worst_of_peak, 3e-6);
        EXPECT_LE(c.worst_of_peak, 0.1 * c.worst_unquantised_of_peak);
      }
    }
  }
}

}  // namespace
}  // namespace relight
