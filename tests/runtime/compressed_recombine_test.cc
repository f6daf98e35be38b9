// The compressed recombination (compressed_recombine.h): the per-cluster
// kernel against an exact int64 reference on lengths that exercise the
// vector path's tails, its AVX2 path bit-identical to the scalar one, the
// multipliers' rounding, limits and saturation, and the whole path against
// the float64 expansion of a compressed basis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "compressed_recombine.h"
#include "compressed_multipliers_avx512.h"
#include "compressed_recombine_avx2.h"
#include "compressed_recombine_vnni.h"
#include "compressed_tiles.h"
#include "recombine_avx2.h"
#include "recombine_dispatch.h"
#include "relight/base/fixed_ops.h"
#include "relight/base/sh_index.h"

namespace relight {
namespace {

std::vector<int32_t> Reference(const std::vector<int16_t>& w, uint32_t n, uint32_t r,
                               const ClusterMultipliers& m) {
  std::vector<int32_t> out(size_t{n} * 3);
  for (int ch = 0; ch < 3; ++ch) {
    for (uint32_t i = 0; i < n; ++i) {
      int64_t acc = 0;
      for (uint32_t j = 0; j < r; ++j) acc += int64_t{w[size_t{j} * n + i]} * m.k[ch * r + j];
      const int s = m.shift[ch];
      const int64_t half = s > 0 ? int64_t{1} << (s - 1) : 0;
      int64_t v = s >= 0 ? m.mean[ch] + ((acc + half) >> s) : m.mean[ch] + acc * (int64_t{1} << -s);
      EXPECT_LE(std::abs(acc), (int64_t{1} << 30) - 1);
      if (s >= 0) {
        EXPECT_TRUE(v >= INT32_MIN && v <= INT32_MAX);  // never saturates
      }
      v = std::min<int64_t>(std::max<int64_t>(v, INT32_MIN), INT32_MAX);
      out[size_t{i} * 3 + ch] = static_cast<int32_t>(v);
    }
  }
  return out;
}

// Random multipliers within the limit (or at it, extreme = true) and weights
// within the format's range (or at its ends).
void Fill(std::mt19937* rng, uint32_t n, uint32_t r, bool extreme, std::vector<int16_t>* w,
          ClusterMultipliers* m) {
  const int32_t limit = CompressedMultiplierLimit(r);
  std::uniform_int_distribution<int32_t> kd(-limit, limit), wd(-kCompressedWeightOne, kCompressedWeightOne);
  std::uniform_int_distribution<int32_t> md(-((1 << 30) - 1), (1 << 30) - 1), sd(-31, 31);
  w->assign(size_t{n} * r, 0);
  for (int16_t& v : *w) v = static_cast<int16_t>(extreme ? kCompressedWeightOne : wd(*rng));
  for (int ch = 0; ch < 3; ++ch) {
    for (uint32_t j = 0; j < r; ++j) {
      m->k[ch * r + j] = static_cast<int16_t>(extreme ? (ch == 1 ? -limit : limit) : kd(*rng));
    }
    m->mean[ch] = extreme ? (ch == 1 ? -((1 << 30) - 1) : (1 << 30) - 1) : md(*rng);
    m->shift[ch] = extreme ? 0 : sd(*rng);
    if (!extreme && (*rng)() % 4 != 0 && m->shift[ch] < 0) m->shift[ch] = -m->shift[ch];
  }
}

// Every vector path (AVX2, AVX-VNNI, AVX-512 VNNI: those this CPU has) called
// directly, and CompressedClusterQ12 under every cap (recombine_dispatch.h),
// against the exact reference: lengths around the 16- and 32-receiver steps.
TEST(CompressedClusterTest, ScalarIsExactAndEveryVectorPathBitIdenticalOnEveryTail) {
  for (int l = 0; l <= static_cast<int>(SimdLevel::kAvx512Vnni); ++l) {
    const SimdLevel level = static_cast<SimdLevel>(l);
    std::printf("%s: %s\n", SimdLevelName(level), CpuSupportsSimdLevel(level) ? "tested" : "not on this CPU");
  }
  const SimdLevel before = ActiveSimdLevel();  // restored after: a cap is process-wide
  std::mt19937 rng(5);
  for (uint32_t r : {0u, 1u, 2u, 3u, 5u, 8u, 16u, 17u, 32u, 64u}) {
    for (uint32_t n : {1u, 3u, 8u, 11u, 16u, 17u, 31u, 32u, 35u, 48u, 63u, 100u, 129u}) {
      for (bool extreme : {false, true}) {
        SCOPED_TRACE(testing::Message() << "r " << r << " n " << n << " extreme " << extreme);
        std::vector<int16_t> w;
        ClusterMultipliers m{};
        Fill(&rng, n, r, extreme, &w, &m);
        const bool vector_path = m.shift[0] >= 0 && m.shift[1] >= 0 && m.shift[2] >= 0;
        const std::vector<int32_t> want = Reference(w, n, r, m);  // component-major, as in the file
        std::vector<int16_t> tiled(w.size());
        TileClusterWeights(w.data(), n, r, tiled.data());
        w = tiled;  // what every path reads (compressed_tiles.h)
        std::vector<int32_t> scalar(size_t{n} * 3, 0x5A5A5A5A);
        CompressedClusterScalarQ12(w.data(), n, r, m, scalar.data());
        EXPECT_EQ(scalar, want);
        for (int l = 0; l <= static_cast<int>(SimdLevel::kAvx512Vnni); ++l) {
          SetSimdLevelCap(static_cast<SimdLevel>(l));
          std::vector<int32_t> any(size_t{n} * 3, 0x5A5A5A5A);
          CompressedClusterQ12(w.data(), n, r, m, any.data());
          EXPECT_EQ(any, want) << "cap " << SimdLevelName(static_cast<SimdLevel>(l));
        }
        SetSimdLevelCap(before);
        // The 512-bit body does every receiver (masked last step) at every
        // shift, negative ones included, and writes nothing past them.
        if (CpuSupportsSimdLevel(SimdLevel::kAvx512Vnni)) {
          std::vector<int32_t> vec(size_t{n} * 3 + 64, 0x5A5A5A5A);
          CompressedClusterAvx512VnniQ12(w.data(), n, r, m, vec.data());
          EXPECT_TRUE(std::equal(want.begin(), want.end(), vec.begin())) << "vector_path " << vector_path;
          for (size_t e = want.size(); e < vec.size(); ++e) EXPECT_EQ(vec[e], 0x5A5A5A5A);
        }
        // The 16-receiver bodies leave the tail (n % 16) untouched; the AVX2
        // one takes negative shifts too, AVX-VNNI's only the others.
        const size_t done = size_t{n - n % 16} * 3;
        using Body = void (*)(const int16_t*, uint32_t, uint32_t, const ClusterMultipliers&, int32_t*);
        const std::pair<SimdLevel, Body> bodies[] = {{SimdLevel::kAvx2, CompressedClusterAvx2Q12},
                                                     {SimdLevel::kAvxVnni, CompressedClusterAvxVnniQ12}};
        for (const auto& [level, body] : bodies) {
          if (!CpuSupportsSimdLevel(level) || n < 16) continue;
          if (level == SimdLevel::kAvxVnni && !vector_path) continue;
          std::vector<int32_t> vec(size_t{n} * 3, 0x5A5A5A5A);
          body(w.data(), n, r, m, vec.data());
          EXPECT_TRUE(std::equal(vec.begin(), vec.begin() + static_cast<long>(done), want.begin()))
              << SimdLevelName(level);
          for (size_t e = done; e < vec.size(); ++e) EXPECT_EQ(vec[e], 0x5A5A5A5A) << SimdLevelName(level);
        }
      }
    }
  }
}

// 8-bit weights (weight_bits 8): every path over int8 tiles against the
// exact reference, with multipliers up to the limit a weight of 127 allows;
// negative weights in an odd r's last component check that the sign-
// extending load's high half is ignored (its multiplier pair is (K, 0)).
TEST(CompressedClusterTest, EightBitWeightsGiveTheExactIntegersOnEveryPathAndTail) {
  const SimdLevel before = ActiveSimdLevel();
  std::mt19937 rng(17);
  for (uint32_t r : {1u, 2u, 3u, 5u, 8u, 16u, 17u, 32u, 33u, 64u}) {
    const int32_t limit = CompressedMultiplierLimit(r, kCompressedWeightOne8);
    EXPECT_LE(int64_t{limit} * r * kCompressedWeightOne8, (int64_t{1} << 30) - 1);
    for (uint32_t n : {1u, 7u, 15u, 16u, 17u, 31u, 32u, 33u, 47u, 64u, 100u}) {
      for (bool extreme : {false, true}) {
        SCOPED_TRACE(testing::Message() << "r " << r << " n " << n << " extreme " << extreme);
        std::uniform_int_distribution<int32_t> kd(-limit, limit), wd(-kCompressedWeightOne8, kCompressedWeightOne8);
        // Shifts from -31 (bright clusters, which 8-bit weights reach first) to 31.
        std::uniform_int_distribution<int32_t> md(-((1 << 30) - 1), (1 << 30) - 1), sd(-31, 31);
        std::vector<int16_t> w(size_t{n} * r);
        for (int16_t& v : w) v = static_cast<int16_t>(extreme ? -kCompressedWeightOne8 : wd(rng));
        ClusterMultipliers m{};
        for (int ch = 0; ch < 3; ++ch) {
          for (uint32_t j = 0; j < r; ++j) m.k[ch * r + j] = static_cast<int16_t>(extreme ? limit : kd(rng));
          m.mean[ch] = extreme ? -((1 << 30) - 1) : md(rng);
          m.shift[ch] = extreme ? 0 : sd(rng);
        }
        const std::vector<int32_t> want = Reference(w, n, r, m);
        std::vector<int16_t> tiled(w.size());
        TileClusterWeights(w.data(), n, r, tiled.data());
        const std::vector<int8_t> bytes(tiled.begin(), tiled.end());
        std::vector<int32_t> scalar(size_t{n} * 3, 0x5A5A5A5A);
        CompressedClusterScalarQ12(bytes.data(), n, r, m, scalar.data());
        EXPECT_EQ(scalar, want);
        for (int l = 0; l <= static_cast<int>(SimdLevel::kAvx512Vnni); ++l) {
          SetSimdLevelCap(static_cast<SimdLevel>(l));
          std::vector<int32_t> any(size_t{n} * 3, 0x5A5A5A5A);
          CompressedClusterQ12(bytes.data(), n, r, m, any.data());
          EXPECT_EQ(any, want) << "cap " << SimdLevelName(static_cast<SimdLevel>(l));
        }
        SetSimdLevelCap(before);
        if (CpuSupportsSimdLevel(SimdLevel::kAvx512Vnni)) {
          std::vector<int32_t> vec(size_t{n} * 3 + 64, 0x5A5A5A5A);
          CompressedClusterAvx512VnniQ12(bytes.data(), n, r, m, vec.data());
          EXPECT_TRUE(std::equal(want.begin(), want.end(), vec.begin()));
          for (size_t e = want.size(); e < vec.size(); ++e) EXPECT_EQ(vec[e], 0x5A5A5A5A);
        }
        // The AVX2 body at every shift, negative ones included (most of
        // this test's): the full tiles, the tail untouched.
        if (CpuSupportsSimdLevel(SimdLevel::kAvx2) && n >= 16) {
          const size_t done = size_t{n - n % 16} * 3;
          std::vector<int32_t> vec(size_t{n} * 3, 0x5A5A5A5A);
          CompressedClusterAvx2Q12(bytes.data(), n, r, m, vec.data());
          EXPECT_TRUE(std::equal(vec.begin(), vec.begin() + static_cast<long>(done), want.begin()));
          for (size_t e = done; e < vec.size(); ++e) EXPECT_EQ(vec[e], 0x5A5A5A5A);
        }
      }
    }
  }
}

TEST(CompressedClusterTest, MultipliersRoundWithTheLargestShiftUpToInt32Extremes) {
  std::mt19937 rng(9);
  for (uint32_t r : {1u, 4u, 16u, 64u}) {
    const int32_t limit = CompressedMultiplierLimit(r);
    EXPECT_LE(int64_t{r} * kCompressedWeightOne * limit, (int64_t{1} << 30) - 1);
    EXPECT_LE(limit, kCompressedWeightOne);
    for (int trial = 0; trial < 50; ++trial) {
      const int bits = std::uniform_int_distribution<int>(0, 30)(rng);
      std::uniform_int_distribution<int32_t> pd(-(1 << bits), 1 << bits);
      std::vector<int32_t> projection(3 * (r + 1));
      for (int32_t& p : projection) p = pd(rng);
      ClusterMultipliers m{};
      ClusterMultipliersQ12(projection.data(), r, kCompressedWeightOne, &m);
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_EQ(m.mean[ch], projection[ch]);
        const int s = m.shift[ch];
        ASSERT_TRUE(s >= -31 && s <= 31);
        double largest = 0;
        for (uint32_t j = 0; j < r; ++j) {
          const double exact = std::ldexp(projection[(1 + j) * 3 + ch], s) / kCompressedWeightOne;
          EXPECT_LE(std::abs(m.k[ch * r + j]), limit);
          EXPECT_LE(std::abs(m.k[ch * r + j] - exact), 0.5 + 1e-9) << "j " << j << " s " << s;
          largest = std::max(largest, std::abs(exact));
        }
        // The largest shift: one more would pass the limit (or s is already 31).
        if (s < 31) {
          EXPECT_GT(std::round(2 * largest), limit);
        }
      }
    }
  }
  // The extremes: int32's largest components take negative shifts and stay
  // within half a step; a zero component takes the largest shift.
  std::vector<int32_t> huge = {5, 6, 7, INT32_MAX, INT32_MIN, 0};
  ClusterMultipliers m{};
  ClusterMultipliersQ12(huge.data(), 1, kCompressedWeightOne, &m);
  for (int ch = 0; ch < 2; ++ch) {
    EXPECT_LT(m.shift[ch], 0);
    EXPECT_LE(std::abs(m.k[ch]), CompressedMultiplierLimit(1));
    EXPECT_LE(std::abs(m.k[ch] - std::ldexp(huge[3 + ch], m.shift[ch]) / kCompressedWeightOne), 0.5);
  }
  EXPECT_EQ(m.shift[2], 31);
  EXPECT_EQ(m.k[2], 0);
}

// The AVX-512 multipliers (compressed_multipliers_avx512.h) are the packed
// pairs of the scalar ones, bit for bit, and refuse exactly the clusters with
// a negative shift: random projections of every magnitude, and dividends on
// both sides of every multiple of the weight of 1 up to the limit (the
// multiply-and-shift division's worst places).
TEST(CompressedClusterTest, VectorMultipliersArePairsOfTheScalarOnes) {
  if (!CpuSupportsSimdLevel(SimdLevel::kAvx512Vnni)) GTEST_SKIP() << "no AVX-512 VNNI on this CPU";
  int taken = 0, refused = 0;
  const auto check = [&](const std::vector<int32_t>& projection, uint32_t r, int32_t one) {
    ClusterMultipliers m{};
    ClusterMultipliersQ12(projection.data(), r, one, &m);
    // The pairs as the kernel packs them: K_2p low 16 bits, K_2p+1 high (0 past r).
    const auto pair = [&](int ch, uint32_t p) {
      const uint32_t lo = static_cast<uint16_t>(m.k[ch * r + 2 * p]);
      const uint32_t hi = 2 * p + 1 < r ? static_cast<uint16_t>(m.k[ch * r + 2 * p + 1]) : 0u;
      return static_cast<int32_t>((hi << 16) | lo);
    };
    PackedClusterMultipliers got{};
    const bool negative = m.shift[0] < 0 || m.shift[1] < 0 || m.shift[2] < 0;
    const bool ok = ClusterMultipliersAvx512(projection.data(), r, one, &got);
    ASSERT_EQ(ok, !negative) << "r " << r << " one " << one;
    if (!ok) return ++refused, void();
    ++taken;
    for (int ch = 0; ch < 3; ++ch) {
      ASSERT_EQ(got.mean[ch], m.mean[ch]);
      ASSERT_EQ(got.shift[ch], m.shift[ch]);
      for (uint32_t p = 0; p < (r + 1) / 2; ++p)
        ASSERT_EQ(got.packed[ch][p], pair(ch, p)) << "r " << r << " one " << one << " ch " << ch << " pair " << p;
    }
  };
  std::mt19937_64 rng(31);
  for (const int32_t one : {int32_t{kCompressedWeightOne}, int32_t{kCompressedWeightOne8}}) {
    for (uint32_t r : {0u, 1u, 2u, 3u, 7u, 16u, 17u, 31u, 32u, 64u}) {
      for (int trial = 0; trial < 200; ++trial) {
        const int bits = static_cast<int>(rng() % 32);
        std::vector<int32_t> projection(3 * (r + 1));
        for (int32_t& p : projection) {
          const int64_t v = static_cast<int64_t>(rng() % (uint64_t{1} << bits)) * (rng() % 2 ? 1 : -1);
          p = trial % 17 == 0 ? 0 : static_cast<int32_t>(v);
        }
        if (trial % 23 == 1 && r > 0) projection[3] = INT32_MIN;
        if (trial % 29 == 2 && r > 0) projection[4] = INT32_MAX;
        check(projection, r, one);
      }
    }
    // Shift 0 (the largest component at limit x one), the others' dividends
    // q one - 1, q one, q one + one - 1 for every q up to the limit.
    const uint32_t r = one == kCompressedWeightOne8 ? 64 : 4;
    const int64_t limit = CompressedMultiplierLimit(r, one);
    std::vector<int64_t> magnitudes;
    for (int64_t q = 0; q <= limit; ++q)
      for (const int64_t x : {q * one - 1, q * one, q * one + one - 1})
        if (x - one / 2 >= 0 && x - one / 2 <= limit * one) magnitudes.push_back(x - one / 2);
    std::vector<int32_t> projection(3 * (r + 1), 0);
    for (int ch = 0; ch < 3; ++ch) projection[3 + ch] = static_cast<int32_t>(limit * one) * (ch == 1 ? -1 : 1);
    size_t next = 0;
    while (next < magnitudes.size()) {
      for (uint32_t j = 1; j < r; ++j)
        for (int ch = 0; ch < 3; ++ch) {
          const int64_t a = magnitudes[next < magnitudes.size() ? next++ : magnitudes.size() - 1];
          projection[3 * (1 + j) + ch] = static_cast<int32_t>(ch == 2 ? -a : a);
        }
      ClusterMultipliers m{};
      ClusterMultipliersQ12(projection.data(), r, one, &m);
      ASSERT_EQ(m.shift[0], 0);
      check(projection, r, one);
    }
  }
  EXPECT_GT(taken, 1000);
  EXPECT_GT(refused, 10);
}

// The shift ClusterMultipliersQ12 picks from bit lengths is the one the
// definition's walk down from 31 finds (one 128-bit division a step here).
TEST(CompressedClusterTest, ShiftIsTheLargestThatFitsExactly) {
  std::mt19937_64 rng(23);
  for (const int32_t one : {int32_t{kCompressedWeightOne}, int32_t{kCompressedWeightOne8}}) {
    for (uint32_t r : {1u, 2u, 7u, 8u, 16u, 32u}) {
      const int64_t limit = CompressedMultiplierLimit(r, one);
      for (int trial = 0; trial < 3000; ++trial) {
        const int bits = static_cast<int>(rng() % 32);
        std::vector<int32_t> projection(3 * (r + 1));
        for (int32_t& p : projection) {
          p = static_cast<int32_t>(static_cast<int64_t>(rng() % (uint64_t{1} << bits)) * (rng() % 2 ? 1 : -1));
        }
        if (trial == 0) projection[3] = INT32_MIN;
        ClusterMultipliers m{};
        ClusterMultipliersQ12(projection.data(), r, one, &m);
        for (int ch = 0; ch < 3; ++ch) {
          Int128 largest = 0;
          for (uint32_t j = 0; j < r; ++j) {
            const Int128 p = projection[(1 + j) * 3 + ch];
            largest = std::max(largest, p < 0 ? -p : p);
          }
          const auto scaled = [&](int s) {  // round(a 2^s / one), halves up
            const Int128 num = s >= 0 ? largest << s : largest, den = s >= 0 ? Int128{one} : Int128{one} << -s;
            return (num + den / 2) / den;
          };
          int s = 31;
          while (s > -31 && scaled(s) > limit) --s;
          ASSERT_EQ(m.shift[ch], s) << "one " << one << " r " << r << " largest " << static_cast<int64_t>(largest);
          for (uint32_t j = 0; j < r; ++j) ASSERT_LE(std::abs(int32_t{m.k[ch * r + j]}), limit);
        }
      }
    }
  }
}

// The tiled order (compressed_tiles.h) is a permutation of each cluster's
// n x r weights, has the layout the vector bodies load (a full tile's pair p
// of receiver q at 32 p + 2 q, an odd last component at 32 (r / 2) + q), and
// TileCompressedWeights reorders every cluster in place, once.
TEST(CompressedTilesTest, EveryClusterIsPermutedInPlaceIntoTheKernelsLayout) {
  for (uint32_t r : {0u, 1u, 2u, 5u, 16u, 17u}) {
    for (uint32_t n : {1u, 15u, 16u, 17u, 33u, 64u}) {
      SCOPED_TRACE(testing::Message() << "r " << r << " n " << n);
      std::vector<int> seen(size_t{n} * r, 0);
      for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < r; ++j) {
          const size_t at = TiledWeightOffset(n, r, i, j);
          ASSERT_LT(at, seen.size());
          ++seen[at];
          if (i - i % 16 + 16 > n) continue;  // the short last tile: checked by the kernels' test
          const size_t tile = size_t{i - i % 16} * r, q = i % 16;
          EXPECT_EQ(at, j < (r & ~1u) ? tile + 32 * (j / 2) + 2 * q + j % 2 : tile + 32 * (r / 2) + q);
        }
      }
      EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int c) { return c == 1; }));
    }
  }
  BakeCompressedBasis cpca;
  cpca.components = 3;
  cpca.cluster_start = {0, 32, 49, 50};
  for (int i = 0; i < 50 * 3; ++i) cpca.weights.push_back(static_cast<int16_t>(i - 75));
  const std::vector<int16_t> file = cpca.weights;
  TileCompressedWeights(&cpca);
  EXPECT_EQ(cpca.weight_order, CompressedWeightOrder::kTiles16);
  for (uint32_t c = 0; c < 3; ++c) {
    const uint32_t start = cpca.cluster_start[c], n = cpca.cluster_start[c + 1] - start;
    std::vector<int16_t> want(size_t{n} * 3);
    TileClusterWeights(file.data() + size_t{start} * 3, n, 3, want.data());
    EXPECT_TRUE(std::equal(want.begin(), want.end(), cpca.weights.begin() + start * 3)) << "cluster " << c;
  }
  const std::vector<int16_t> once = cpca.weights;
  TileCompressedWeights(&cpca);  // already tiled: unchanged
  EXPECT_EQ(cpca.weights, once);
  EXPECT_NE(once, file);
}

TEST(CompressedRecombineTest, MatchesTheFloat64ExpansionOfTheCompressedBasis) {
  const int degree = 2, terms = ShTermCount(degree);
  const uint32_t r = 5, counts[] = {20, 37, 16};
  std::mt19937 rng(17);
  BakeCompressedBasis cpca;
  cpca.components = r;
  cpca.cluster_start = {0};
  for (uint32_t n : counts) cpca.cluster_start.push_back(cpca.cluster_start.back() + n);
  const uint32_t receivers = cpca.cluster_start.back(), vectors = 3 * (r + 1);
  std::uniform_int_distribution<int32_t> q16(-32767, 32767), wq(-kCompressedWeightOne, kCompressedWeightOne);
  std::uniform_int_distribution<int32_t> mant(1 << 29, (1 << 30) - 1);
  for (int i = 0; i < 3 * terms; ++i) cpca.vector_scale.push_back(QuantScale{mant(rng), -22});  // ~2^-22 per LSB
  for (uint32_t i = 0; i < 3 * terms * vectors; ++i) cpca.vectors.push_back(static_cast<int16_t>(q16(rng)));
  for (uint32_t i = 0; i < receivers * r; ++i) cpca.weights.push_back(static_cast<int16_t>(wq(rng)));
  std::vector<int64_t> coef(static_cast<size_t>(terms));
  for (int64_t& c : coef) c = int64_t{std::uniform_int_distribution<int>(-3000, 3000)(rng)} * 65536;  // cd, Q16

  std::vector<int32_t> k(3 * static_cast<size_t>(terms)), projection(CompressedProjectionValues(cpca));
  std::vector<int64_t> scratch(64);
  std::vector<int32_t> out(size_t{receivers} * 3);
  BakeCompressedBasis tiled = cpca;  // the engine's order; cpca keeps the file's for the reference
  TileCompressedWeights(&tiled);
  RecombineCompressedQ12(tiled, terms, coef.data(), k.data(), scratch.data(), 64, projection.data(), out.data());

  const auto value = [&](uint32_t vec, int t, int ch) {
    const QuantScale s = cpca.vector_scale[static_cast<size_t>(t * 3 + ch)];
    return cpca.vectors[(size_t{static_cast<uint32_t>(t)} * 3 * (r + 1) + vec) * 3 + static_cast<size_t>(ch)] *
           std::ldexp(s.mantissa, s.exponent - 30);
  };
  double peak = 0, worst = 0;
  for (uint32_t c = 0; c < 3; ++c) {
    const uint32_t start = cpca.cluster_start[c], n = counts[c];
    for (uint32_t i = 0; i < n; ++i) {
      for (int ch = 0; ch < 3; ++ch) {
        double want = 0;  // cd/m^2
        for (int t = 0; t < terms; ++t) {
          double v = value(c * (r + 1), t, ch);
          for (uint32_t j = 0; j < r; ++j) {
            v += cpca.weights[size_t{start} * r + size_t{j} * n + i] / double{kCompressedWeightOne} *
                 value(c * (r + 1) + 1 + j, t, ch);
          }
          want += static_cast<double>(coef[static_cast<size_t>(t)] >> 16) * v;
        }
        const double got = out[size_t{start + i} * 3 + static_cast<size_t>(ch)] / 4096.0;
        peak = std::max(peak, std::abs(want));
        worst = std::max(worst, std::abs(got - want));
      }
    }
  }
  ASSERT_GT(peak, 1.0);
  // Projection rounding (half a Q12 step per vector) and multiplier rounding
  // (half a step of 2^-s per weight): well under 1e-3 of the peak.
  EXPECT_LT(worst, 1e-3 * peak) << "worst " << worst << " cd/m^2 of peak " << peak;
}

}  // namespace
}  // namespace relight
