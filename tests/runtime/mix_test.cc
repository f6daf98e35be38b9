// Mixing cached luminaire results (mix.h): the AVX2 and AVX-512 bodies against the scalar
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
#include "mix_avx512.h"
#include "recombine_dispatch.h"
#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

constexpr int32_t kMin32 = std::numeric_limits<int32_t>::min();
constexpr int32_t kMax32 = std::numeric_limits<int32_t>::max();

using AddBody = void (*)(const int32_t*, const int64_t*, uint32_t, int64_t*);
using SaturateBody = void (*)(const int64_t*, uint32_t, int32_t*);

// Elements 3 .. 75: every tail of the AVX2 (12) and AVX-512 (24) steps; the
// buffers have 8 guard elements that must stay as they were.
void ExpectAddsExactlyAsTheScalarFormula(AddBody body) {
  std::mt19937_64 rng(17);
  std::uniform_int_distribution<int32_t> any32(kMin32, kMax32);
  std::uniform_int_distribution<int64_t> gain(0, int64_t{1} << 30), acc0(-(int64_t{1} << 40), int64_t{1} << 40);
  for (uint32_t elements = 3; elements <= 75; elements += 3) {
    for (int round = 0; round < 50; ++round) {
      std::vector<int32_t> a(elements + 8, 0x5A5A5A5A);
      for (uint32_t e = 0; e < elements; ++e) {
        const int pick = static_cast<int>(rng() % 6);
        a[e] = pick == 0 ? kMin32 : (pick == 1 ? kMax32 : (pick == 2 ? -1 : any32(rng)));
      }
      int64_t g[3];
      for (int64_t& v : g) {
        const int pick = static_cast<int>(rng() % 4);
        v = pick == 0 ? 0 : (pick == 1 ? int64_t{1} << 30 : gain(rng));
      }
      std::vector<int64_t> expect(elements + 8), got(elements + 8);
      for (uint32_t e = 0; e < elements + 8; ++e) expect[e] = got[e] = acc0(rng);
      for (uint32_t e = 0; e < elements; ++e) {
        expect[e] += (static_cast<int64_t>(a[e]) * g[e % 3] + (int64_t{1} << 29)) >> 30;
      }
      body(a.data(), g, elements, got.data());
      ASSERT_EQ(got, expect) << "elements " << elements;
    }
  }
}

void ExpectSaturatesExactly(SaturateBody body) {
  const int64_t edges[] = {0, 1, -1, kMax32, int64_t{kMax32} + 1, kMin32, int64_t{kMin32} - 1,
                           std::numeric_limits<int64_t>::max(), std::numeric_limits<int64_t>::min(),
                           int64_t{1} << 40, -(int64_t{1} << 40)};
  std::mt19937_64 rng(3);
  for (uint32_t elements = 1; elements <= 23; ++elements) {
    std::vector<int64_t> acc(elements);
    for (int64_t& v : acc) v = edges[rng() % (sizeof edges / sizeof edges[0])];
    std::vector<int32_t> got(elements + 8, 0x5A5A5A5A);
    body(acc.data(), elements, got.data());
    for (uint32_t e = 0; e < elements; ++e) ASSERT_EQ(got[e], SaturateI32(acc[e])) << acc[e];
    for (uint32_t e = elements; e < elements + 8; ++e) ASSERT_EQ(got[e], 0x5A5A5A5A) << "written past the end";
  }
}

TEST(MixAvx2, AddsExactlyAsTheScalarFormula) {
  if (!CpuSupportsSimdLevel(SimdLevel::kAvx2)) GTEST_SKIP() << "no AVX2 here";
  ExpectAddsExactlyAsTheScalarFormula(MixAddAvx2);
}

TEST(MixAvx2, SaturatesExactly) {
  if (!CpuSupportsSimdLevel(SimdLevel::kAvx2)) GTEST_SKIP() << "no AVX2 here";
  ExpectSaturatesExactly(SaturateAvx2);
}

TEST(MixAvx512, AddsExactlyAsTheScalarFormula) {
  if (!CpuSupportsSimdLevel(SimdLevel::kAvx512Vnni)) GTEST_SKIP() << "no AVX-512 here";
  ExpectAddsExactlyAsTheScalarFormula(MixAddAvx512);
}

TEST(MixAvx512, SaturatesExactly) {
  if (!CpuSupportsSimdLevel(SimdLevel::kAvx512Vnni)) GTEST_SKIP() << "no AVX-512 here";
  ExpectSaturatesExactly(SaturateAvx512);
}

// The whole mix under every cap (recombine_dispatch.h) gives the scalar path's
// bits: vertex sources (a alone: the vector bodies) and grid sources (a + b:
// scalar on every path), receivers that leave every tail, blocks of 5.
TEST(Mix, EveryPathGivesTheSameBits) {
  const SimdLevel before = ActiveSimdLevel();
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<int32_t> any32(kMin32, kMax32);
  std::uniform_int_distribution<int32_t> gain(0, 1 << 30);
  for (uint32_t receivers : {1u, 7u, 8u, 9u, 31u, 64u, 101u}) {
    std::vector<std::vector<int32_t>> light(6, std::vector<int32_t>(size_t{receivers} * 3));
    for (auto& l : light) {
      for (int32_t& v : l) v = rng() % 5 == 0 ? (rng() % 2 ? kMax32 : kMin32) : any32(rng);
    }
    MixSource sources[4];
    for (int i = 0; i < 4; ++i) {
      sources[i].a = light[i].data();
      sources[i].b = i >= 2 ? light[i + 2].data() : nullptr;
      for (Q1_30& g : sources[i].gain) g = Q1_30::FromRaw(rng() % 4 == 0 ? (1 << 30) : gain(rng));
    }
    std::vector<int32_t> want;
    for (int level = 0; level <= static_cast<int>(SimdLevel::kAvx512Vnni); ++level) {
      SetSimdLevelCap(static_cast<SimdLevel>(level));
      std::vector<int64_t> scratch(15);
      std::vector<int32_t> out(size_t{receivers} * 3, 0x5A5A5A5A);
      MixLuminairesQ12(sources, 4, receivers, scratch.data(), static_cast<uint32_t>(scratch.size()), out.data());
      if (level == 0) want = out;
      EXPECT_EQ(out, want) << "receivers " << receivers << " cap " << SimdLevelName(static_cast<SimdLevel>(level));
    }
  }
  SetSimdLevelCap(before);
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
