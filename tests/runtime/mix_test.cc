// Mixing cached luminaire results (mix.h): the AVX2 body against the scalar
// formula bit for bit (extremes of int32 light and of the gains, lengths
// that leave loop tails), saturation exactly, and the whole mix against a
// float64 reference within half an LSB per luminaire.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "mix.h"
#include "mix_avx2.h"
#include "recombine_avx2.h"
#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

constexpr int32_t kMin32 = std::numeric_limits<int32_t>::min();
constexpr int32_t kMax32 = std::numeric_limits<int32_t>::max();

TEST(MixAvx2, AddsExactlyAsTheScalarFormula) {
  if (!CpuHasAvx2()) GTEST_SKIP() << "no AVX2 here (or RELIGHT_FORCE_SCALAR)";
  std::mt19937_64 rng(17);
  std::uniform_int_distribution<int32_t> any32(kMin32, kMax32);
  std::uniform_int_distribution<int64_t> gain(0, int64_t{1} << 30), acc0(-(int64_t{1} << 40), int64_t{1} << 40);
  for (uint32_t elements = 3; elements <= 75; elements += 3) {
    for (int round = 0; round < 50; ++round) {
      std::vector<int32_t> a(elements);
      for (uint32_t e = 0; e < elements; ++e) {
        const int pick = static_cast<int>(rng() % 6);
        a[e] = pick == 0 ? kMin32 : (pick == 1 ? kMax32 : (pick == 2 ? -1 : any32(rng)));
      }
      int64_t g[3];
      for (int64_t& v : g) {
        const int pick = static_cast<int>(rng() % 4);
        v = pick == 0 ? 0 : (pick == 1 ? int64_t{1} << 30 : gain(rng));
      }
      std::vector<int64_t> expect(elements), got(elements);
      for (uint32_t e = 0; e < elements; ++e) expect[e] = got[e] = acc0(rng);
      for (uint32_t e = 0; e < elements; ++e) {
        expect[e] += (static_cast<int64_t>(a[e]) * g[e % 3] + (int64_t{1} << 29)) >> 30;
      }
      MixAddAvx2(a.data(), g, elements, got.data());
      ASSERT_EQ(got, expect) << "elements " << elements;
    }
  }
}

TEST(MixAvx2, SaturatesExactly) {
  if (!CpuHasAvx2()) GTEST_SKIP() << "no AVX2 here (or RELIGHT_FORCE_SCALAR)";
  const int64_t edges[] = {0, 1, -1, kMax32, int64_t{kMax32} + 1, kMin32, int64_t{kMin32} - 1,
                           std::numeric_limits<int64_t>::max(), std::numeric_limits<int64_t>::min(),
                           int64_t{1} << 40, -(int64_t{1} << 40)};
  std::mt19937_64 rng(3);
  for (uint32_t elements = 1; elements <= 23; ++elements) {
    std::vector<int64_t> acc(elements);
    for (int64_t& v : acc) v = edges[rng() % (sizeof edges / sizeof edges[0])];
    std::vector<int32_t> got(elements);
    SaturateAvx2(acc.data(), elements, got.data());
    for (uint32_t e = 0; e < elements; ++e) ASSERT_EQ(got[e], SaturateI32(acc[e])) << acc[e];
  }
}

TEST(Mix, MatchesFloatWithinHalfAnLsbPerLuminaire) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int32_t> light(-(1 << 20), 1 << 28);
  std::uniform_int_distribution<int> level(0, 32767);
  constexpr uint32_t kReceivers = 5003;  // blocks and tails
  constexpr uint32_t kSources = 7;
  std::vector<std::vector<int32_t>> a(kSources, std::vector<int32_t>(kReceivers * 3)), b = a;
  std::vector<MixSource> sources(kSources);
  for (uint32_t l = 0; l < kSources; ++l) {
    for (int32_t& v : a[l]) v = light(rng);
    for (int32_t& v : b[l]) v = light(rng) / 8;
    const Q1_15 dimmer = Q1_15::FromRaw(static_cast<int16_t>(level(rng)));
    for (int c = 0; c < 3; ++c) {
      sources[l].gain[c] = GainQ30(dimmer, Q1_15::FromRaw(static_cast<int16_t>(level(rng))));
    }
    sources[l].a = a[l].data();
    sources[l].b = l % 3 == 1 ? b[l].data() : nullptr;  // some with a direct part
  }
  std::vector<int64_t> scratch(3 * 1000);
  std::vector<int32_t> out(kReceivers * 3);
  MixLuminairesQ12(sources.data(), kSources, kReceivers, scratch.data(), static_cast<uint32_t>(scratch.size()),
                   out.data());
  double worst = 0;
  for (uint32_t e = 0; e < kReceivers * 3; ++e) {
    double ref = 0;
    for (uint32_t l = 0; l < kSources; ++l) {
      const double v = a[l][e] + (sources[l].b ? b[l][e] : 0);
      ref += v * sources[l].gain[e % 3].raw() / double{1 << 30};
    }
    ref = std::fmin(std::fmax(ref, -2147483648.0), 2147483647.0);
    worst = std::fmax(worst, std::fabs(out[e] - ref));
  }
  EXPECT_LE(worst, 0.5 * kSources);
}

}  // namespace
}  // namespace relight
