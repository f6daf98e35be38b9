// Weights (weights.h) and the recombination kernel (recombine.h) against
// float64: the same unquantised basis recombined with the float photometry's
// weights, exact integer references for loop tails and saturation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "engine_test_support.h"
#include "recombine.h"
#include "recombine_avx2.h"
#include "recombine_dispatch.h"
#include "recombine_vnni.h"
#include "relight/baker/photometry.h"
#include "relight/engine/sh_eval.h"
#include "relight/base/sh_index.h"
#include "weights.h"

namespace relight {
namespace {

using baker::MountingKind;
using testing::Vec3;

constexpr double kQ12 = 4096.0;

struct Aim {
  double pan_deg, tilt_deg;
};
const Aim kAims[] = {{0, 0}, {30, 20}, {135, 45}, {-60, 70}, {170, 110}};

// A smooth synthetic basis, term-major [t][r][c], in cd/m^2 per cd of Y_t:
// the direct light of a point source on a floor (Y_t(dir) cos / d^2 rho/pi)
// plus a random low-frequency field per term (fixed seed).
struct SyntheticBasis {
  int degree = 8;
  uint32_t count = 0;
  std::vector<double> values;
};

SyntheticBasis MakeBasis(int degree, uint32_t count, uint32_t seed) {
  SyntheticBasis b;
  b.degree = degree;
  b.count = count;
  const int terms = ShTermCount(degree);
  b.values.assign(static_cast<size_t>(terms) * count * 3, 0.0);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Vec3 light = {2.0, 1.5, 3.0};
  const double rho[3] = {0.7, 0.5, 0.3};
  std::vector<double> y(terms);
  for (int t = 0; t < terms; ++t) {
    double a[3], f[3], g[3], ph[3];
    for (int j = 0; j < 3; ++j) {
      a[j] = 0.01 * u(rng);
      f[j] = 1.0 + 1.5 * u(rng);
      g[j] = 1.0 + 1.5 * u(rng);
      ph[j] = 3.0 * u(rng);
    }
    for (uint32_t r = 0; r < count; ++r) {
      const double x = 4.0 * (r % 20) / 19.0, yy = 3.0 * (r / 20) / 9.0;
      const Vec3 d = testing::Sub({x, yy, 0.0}, light);
      const double dist = testing::Norm(d);
      baker::EvalShBasis(degree, testing::Normalised(d), y.data());
      const double g_direct = light[2] / dist / (dist * dist);  // cos / d^2
      double smooth = 0;
      for (int j = 0; j < 3; ++j) smooth += a[j] * std::sin(f[j] * x + ph[j]) * std::cos(g[j] * yy);
      for (int c = 0; c < 3; ++c) {
        b.values[(static_cast<size_t>(t) * count + r) * 3 + c] =
            rho[c] / testing::kPi * (y[t] * g_direct + smooth);
      }
    }
  }
  return b;
}

struct QuantisedBasis {
  std::vector<int16_t> q;
  std::vector<QuantScale> scale;  // [t][c]
};

QuantisedBasis Quantise(const SyntheticBasis& b) {
  QuantisedBasis out;
  const int terms = ShTermCount(b.degree);
  out.q.resize(b.values.size());
  out.scale.resize(static_cast<size_t>(terms) * 3);
  for (int t = 0; t < terms; ++t) {
    for (int c = 0; c < 3; ++c) {
      const size_t base = static_cast<size_t>(t) * b.count * 3 + c;
      out.scale[t * 3 + c] =
          testing::QuantiseInt16(&b.values[base], b.count, 3, &out.q[base], 3);
    }
  }
  return out;
}

TEST(RecombineQ12, MatchesFloat64RecombinationOfUnquantisedBasis) {
  constexpr int kDegree = 8;  // 81 terms
  constexpr uint32_t kCount = 200;
  const SyntheticBasis basis = MakeBasis(kDegree, kCount, 12345);
  const QuantisedBasis qb = Quantise(basis);
  const int terms = ShTermCount(kDegree);
  const std::vector<double> w =
      baker::LegendreWeights(testing::CosPowerSamples(1000.0, 10.0, 180), kDegree);
  std::vector<int64_t> coef(terms);
  std::vector<int32_t> k(terms * 3);
  std::vector<int64_t> scratch(64 * 3);  // 200 = 3 x 64 + a tail of 8
  std::vector<int32_t> out(kCount * 3);
  double worst_rel = 0, worst_kernel_lsb = 0;
  for (const Aim& aim : kAims) {
    const std::vector<double> tw =
        baker::TermWeights(w, baker::BeamAxis(MountingKind::kHanging, aim.pan_deg, aim.tilt_deg),
                           true);
    for (int t = 0; t < terms; ++t) coef[t] = std::llround(tw[t] * 65536.0);
    const int shift = ChannelMultipliersQ12(coef.data(), terms, qb.scale.data(), k.data());
    const uint32_t used = RecombineQ12(qb.q.data(), terms, kCount, k.data(), shift, scratch.data(),
                                       static_cast<uint32_t>(scratch.size()), out.data());
    EXPECT_LE(used, static_cast<uint32_t>(terms));
    double peak = 0, max_err = 0, max_kernel = 0;
    for (uint32_t i = 0; i < kCount * 3; ++i) {
      double ref = 0, ref_deq = 0;  // unquantised data; the kernel's own inputs
      for (int t = 0; t < terms; ++t) {
        const size_t at = static_cast<size_t>(t) * kCount * 3 + i;
        ref += tw[t] * basis.values[at];
        ref_deq += static_cast<double>(coef[t]) / 65536.0 * qb.q[at] * testing::ScaleValue(qb.scale[t * 3 + i % 3]);
      }
      peak = std::max(peak, std::fabs(ref));
      max_err = std::max(max_err, std::fabs(out[i] / kQ12 - ref));
      max_kernel = std::max(max_kernel, std::fabs(out[i] - ref_deq * kQ12));
    }
    std::printf("  aim pan %6.1f tilt %6.1f: peak %.4f cd/m2, max |fixed - float64| %.3e cd/m2 "
                "= %.2e of peak; kernel vs its own inputs %.2f LSB (shift %d, %u terms)\n",
                aim.pan_deg, aim.tilt_deg, peak, max_err, max_err / peak, max_kernel, shift, used);
    ASSERT_GT(peak, 1.0);
    EXPECT_LE(max_err, 1e-3 * peak);  // acceptance bar: 0.1% of peak
    EXPECT_LE(max_kernel, 1.0);       // the integer path adds at most its final rounding
    worst_rel = std::max(worst_rel, max_err / peak);
    worst_kernel_lsb = std::max(worst_kernel_lsb, max_kernel);
  }
  std::printf("RecombineQ12 N=8 cos^10: worst %.2e of peak (bar 1e-3), kernel %.2f LSB\n",
              worst_rel, worst_kernel_lsb);
}

// Exact reference: 128-bit sum, round half up, saturate.
int32_t ExactRecombine(const std::vector<int16_t>& q, uint32_t terms, uint32_t count,
                       const std::vector<int32_t>& k, int shift, uint32_t i) {
  Int128 acc = 0;
  for (uint32_t t = 0; t < terms; ++t) {
    acc += static_cast<Int128>(q[(static_cast<size_t>(t) * count) * 3 + i]) * k[t * 3 + i % 3];
  }
  if (shift > 0) acc = (acc + (static_cast<Int128>(1) << (shift - 1))) >> shift;
  if (acc > std::numeric_limits<int32_t>::max()) return std::numeric_limits<int32_t>::max();
  if (acc < std::numeric_limits<int32_t>::min()) return std::numeric_limits<int32_t>::min();
  return static_cast<int32_t>(acc);
}

TEST(RecombineQ12, LoopTailsAreExact) {
  std::mt19937 rng(777);
  std::uniform_int_distribution<int> q16(-32767, 32767);
  std::uniform_int_distribution<int32_t> k32(-(1 << 30), 1 << 30);
  for (uint32_t count : {1u, 3u, 8u, 11u}) {
    for (uint32_t block : {1u, 4u, 512u}) {
      for (int shift : {0, 1, 17, 40}) {
        const uint32_t terms = 81;
        std::vector<int16_t> q(static_cast<size_t>(terms) * count * 3);
        for (auto& v : q) v = static_cast<int16_t>(q16(rng));
        std::vector<int32_t> k(terms * 3);
        for (auto& v : k) v = k32(rng) >> (shift < 20 ? 16 : 0);
        for (int c = 0; c < 3; ++c) k[5 * 3 + c] = 0;  // a skipped term
        std::vector<int64_t> scratch(block * 3);
        std::vector<int32_t> out(count * 3, -1);
        const uint32_t used = RecombineQ12(q.data(), terms, count, k.data(), shift, scratch.data(),
                                           block * 3, out.data());
        EXPECT_EQ(used, terms - 1);
        for (uint32_t i = 0; i < count * 3; ++i) {
          ASSERT_EQ(out[i], ExactRecombine(q, terms, count, k, shift, i))
              << "count " << count << " block " << block << " shift " << shift << " i " << i;
        }
      }
    }
  }
}

TEST(RecombineQ12, SaturatesExactlyAndNeverWraps) {
  constexpr int32_t kMax = std::numeric_limits<int32_t>::max();
  constexpr int32_t kMin = std::numeric_limits<int32_t>::min();
  int64_t scratch[12];
  int32_t out[3];
  // 32767 * 65538 = 2^31 - 2; one more term of 1 reaches INT32_MAX exactly, of 2 exceeds it.
  {
    const int16_t q[6] = {32767, 32767, -32767, 1, 2, -2};
    const int32_t k[6] = {65538, 65538, 65538, 1, 1, 1};
    RecombineQ12(q, 2, 1, k, 0, scratch, 12, out);
    EXPECT_EQ(out[0], kMax);  // exactly representable
    EXPECT_EQ(out[1], kMax);  // 2^31: saturates
    EXPECT_EQ(out[2], kMin);  // exactly -2^31
  }
  // The final rounding can carry over the edge: shift 1, (2^32 - 1 + 1) >> 1 = 2^31.
  {
    const int16_t q[6] = {2, 2, -2, 1, -2, -2};
    const int32_t k[6] = {kMax, kMax, kMax, 1, 1, 1};
    RecombineQ12(q, 2, 1, k, 1, scratch, 12, out);
    EXPECT_EQ(out[0], kMax);      // 2^32 - 1 -> 2^31: saturates
    EXPECT_EQ(out[1], kMax - 1);  // 2^32 - 4 -> 2^31 - 2
    EXPECT_EQ(out[2], kMin);      // -2^32 -> -2^31 exactly
  }
  // The largest possible accumulator: 529 terms (kMaxShDegree 22) of 32767 x (2^31 - 1), both signs.
  {
    const uint32_t terms = ShTermCount(kMaxShDegree);
    std::vector<int16_t> q(terms * 3);
    std::vector<int32_t> k(terms * 3);
    for (uint32_t t = 0; t < terms; ++t) {
      q[t * 3 + 0] = 32767;
      q[t * 3 + 1] = -32767;
      q[t * 3 + 2] = 32767;
      k[t * 3 + 0] = kMax;
      k[t * 3 + 1] = kMax;
      k[t * 3 + 2] = -kMax;
    }
    // |sum| = 529 x 32767 x (2^31 - 1) ~ 2^55.1: saturates for shifts up to 24.
    for (int shift : {0, 23, 24, 31, 62}) {
      RecombineQ12(q.data(), terms, 1, k.data(), shift, scratch, 12, out);
      for (uint32_t c = 0; c < 3; ++c) {
        const int32_t expect = ExactRecombine(q, terms, 1, k, shift, c);
        EXPECT_EQ(out[c], expect) << "shift " << shift;
        if (shift <= 23) {
          EXPECT_EQ(out[c], c == 0 ? kMax : kMin) << "shift " << shift;
        }
      }
    }
  }
}

// The AVX-512 finish of a block (shift, round, clamp to int32) gives the
// scalar formula's integers at every shift, tail length and the accumulator's
// extremes (|acc| < 2^55), and writes nothing past the block.
TEST(RecombineQ12, VectorFinishIsTheScalarRoundShiftAndClamp) {
  if (!CpuSupportsSimdLevel(SimdLevel::kAvx512Vnni)) GTEST_SKIP() << "no AVX-512 VNNI on this CPU";
  std::mt19937_64 rng(99);
  constexpr int64_t kBound = (int64_t{1} << 55) - 1;
  std::uniform_int_distribution<int64_t> any(-kBound, kBound);
  for (uint32_t elements = 0; elements <= 19; ++elements) {
    for (int shift : {0, 1, 7, 23, 24, 31, 32, 40, 62}) {
      std::vector<int64_t> acc(elements);
      for (uint32_t i = 0; i < elements; ++i) {
        const int64_t pick[] = {kBound, -kBound, (int64_t{1} << 31) - 1, -(int64_t{1} << 31), int64_t{1} << 31, -1};
        acc[i] = i % 3 == 0 ? pick[(i / 3) % 6] : any(rng) >> (rng() % 40);
      }
      std::vector<int32_t> out(elements + 8, 12345);
      FinishBlockAvx512(acc.data(), elements, shift, out.data());
      for (uint32_t i = 0; i < elements; ++i) {
        const int64_t half = shift > 0 ? int64_t{1} << (shift - 1) : 0;
        const int64_t v = (acc[i] + half) >> shift;
        const int32_t want = v > std::numeric_limits<int32_t>::max()   ? std::numeric_limits<int32_t>::max()
                             : v < std::numeric_limits<int32_t>::min() ? std::numeric_limits<int32_t>::min()
                                                                       : static_cast<int32_t>(v);
        ASSERT_EQ(out[i], want) << "elements " << elements << " shift " << shift << " i " << i;
      }
      for (uint32_t i = elements; i < out.size(); ++i) ASSERT_EQ(out[i], 12345) << "wrote past the block";
    }
  }
}

// The AVX2 path (used when the CPU has it and |k| < 2^24) must equal the
// exact int64 sum bit for bit: extreme values, odd term counts, zero terms
// skipped, receiver counts with every tail length, several block sizes.
// Every level this CPU has (recombine_dispatch.h: scalar, AVX2, AVX-512 VNNI)
// is run through SetSimdLevelCap.
TEST(RecombineQ12, VectorPathIsBitIdenticalToExactSum) {
  std::printf("AVX2 path %s on this CPU\n", CpuHasAvx2() ? "active" : "NOT available (scalar only)");
  std::printf("AVX-512 VNNI path %s on this CPU\n",
              CpuSupportsSimdLevel(SimdLevel::kAvx512Vnni) ? "tested" : "NOT available");
  const SimdLevel before = ActiveSimdLevel();  // restored after: a cap is process-wide
  std::mt19937 rng(4242);
  const int32_t kMaxK = (int32_t{1} << kVectorMultiplierBits) - 1;
  for (uint32_t receivers : {1u, 5u, 6u, 11u, 16u, 21u, 32u, 37u, 100u, 513u}) {
    for (uint32_t terms : {1u, 2u, 3u, 9u, 17u, 81u}) {
      std::vector<int16_t> basis(static_cast<size_t>(terms) * receivers * 3);
      std::uniform_int_distribution<int> qd(-32768, 32767);
      for (size_t i = 0; i < basis.size(); ++i) {
        basis[i] = static_cast<int16_t>(i % 7 == 0 ? (i % 2 ? 32767 : -32768) : qd(rng));
      }
      std::vector<int32_t> k(terms * 3);
      std::uniform_int_distribution<int32_t> kd(-kMaxK - 1, kMaxK);
      for (size_t i = 0; i < k.size(); ++i) k[i] = (i % 5 == 0) ? (i % 2 ? kMaxK : -kMaxK - 1) : kd(rng);
      if (terms > 2) k[3] = k[4] = k[5] = 0;  // a skipped term
      for (int shift : {0, 13, 31}) {
        std::vector<int32_t> out(receivers * 3);
        for (uint32_t scratch_len : {6u, 48u, 3u * 512u}) {
          for (int level = 0; level <= static_cast<int>(SimdLevel::kAvx512Vnni); ++level) {
            SetSimdLevelCap(static_cast<SimdLevel>(level));
            std::vector<int64_t> scratch(scratch_len);
            RecombineQ12(basis.data(), terms, receivers, k.data(), shift, scratch.data(), scratch_len, out.data());
            for (uint32_t e = 0; e < receivers * 3; ++e) {
              int64_t sum = 0;
              for (uint32_t t = 0; t < terms; ++t) sum += int64_t{basis[(t * receivers) * 3 + e]} * k[t * 3 + e % 3];
              const int64_t half = shift > 0 ? int64_t{1} << (shift - 1) : 0;
              const int64_t v = (sum + half) >> shift;
              const int64_t want = std::min<int64_t>(std::max<int64_t>(v, INT32_MIN), INT32_MAX);
              ASSERT_EQ(out[e], want) << "receivers " << receivers << " terms " << terms << " shift " << shift
                                      << " scratch " << scratch_len << " element " << e << " level "
                                      << SimdLevelName(static_cast<SimdLevel>(level));
            }
          }
        }
      }
    }
  }
  SetSimdLevelCap(before);
}

TEST(Weights, BeamAxisMatchesFloat) {
  for (MountingKind m : {MountingKind::kHanging, MountingKind::kStanding}) {
    for (const Aim& aim : kAims) {
      int32_t axis[3];
      BeamAxisQ30(m == MountingKind::kHanging ? Mounting::kHanging : Mounting::kStanding,
                  Q16_16::FromRatio(std::llround(aim.pan_deg * 1000), 1000),
                  Q16_16::FromRatio(std::llround(aim.tilt_deg * 1000), 1000), axis);
      const Vec3 ref = baker::BeamAxis(m, aim.pan_deg, aim.tilt_deg);
      for (int i = 0; i < 3; ++i) EXPECT_NEAR(axis[i] / 1073741824.0, ref[i], 4e-9);
    }
  }
}

TEST(Weights, TermCoefficientsMatchFloatTermWeights) {
  ShTables tables;
  InitShTables(&tables);
  struct Case {
    int degree;
    bool sigma;
    double exponent;
  };
  double worst = 0;
  for (const Case& cs : {Case{8, true, 10}, Case{8, false, 10}, Case{16, true, 40}, Case{3, true, 1}}) {
    const std::vector<int64_t> cd_q16 = testing::ToQ16(testing::CosPowerSamples(1000, cs.exponent, 180));
    const std::vector<double> w = baker::LegendreWeights(testing::FromQ16(cd_q16), cs.degree);
    std::vector<int32_t> table((cs.degree + 1) * 181);
    int64_t damped[kMaxShDegree + 1];
    ASSERT_TRUE(DampedLegendreWeightsQ16(cs.degree, cs.sigma, cd_q16.data(), 180, table.data(),
                                         damped).ok());
    const int terms = ShTermCount(cs.degree);
    std::vector<int64_t> alm(terms), coef(terms);
    for (const Aim& aim : kAims) {
      const Q16_16 pan = Q16_16::FromRatio(std::llround(aim.pan_deg * 1000), 1000);
      const Q16_16 tilt = Q16_16::FromRatio(std::llround(aim.tilt_deg * 1000), 1000);
      int32_t axis[3];
      BeamAxisQ30(Mounting::kHanging, pan, tilt, axis);
      TermCoefficientsQ16(tables, cs.degree, damped, axis, alm.data(), coef.data());
      const std::vector<double> tw =
          baker::TermWeights(w, baker::BeamAxis(MountingKind::kHanging, aim.pan_deg, aim.tilt_deg),
                             cs.sigma);
      double max_ref = 0, max_err = 0;
      for (int t = 0; t < terms; ++t) {
        max_ref = std::max(max_ref, std::fabs(tw[t]));
        max_err = std::max(max_err, std::fabs(static_cast<double>(coef[t]) / 65536.0 - tw[t]));
      }
      // Stated tolerance: 1e-6 of the largest coefficient (Q16 rounding is
      // 7.6e-6 cd, the largest coefficient here is ~100 cd and more).
      EXPECT_LE(max_err, 1e-6 * max_ref) << "degree " << cs.degree << " pan " << aim.pan_deg;
      worst = std::max(worst, max_err / max_ref);
    }
  }
  std::printf("TermCoefficientsQ16 vs TermWeights: worst %.2e of the largest coefficient\n", worst);
}

TEST(Weights, ChannelMultipliersUseTheRangeAndStayBelow2To24) {
  std::mt19937 rng(99);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    const int terms = 81;
    std::vector<int64_t> coef(terms);
    std::vector<QuantScale> scale(terms * 3);
    const double magnitude = std::pow(10.0, 4 * u(rng));
    for (int t = 0; t < terms; ++t) coef[t] = std::llround(magnitude * u(rng) * 65536.0);
    for (auto& s : scale) s = testing::ToQuantScale(std::pow(10.0, -3 + 2 * u(rng)) / 32767.0);
    std::vector<int32_t> k(terms * 3);
    const int shift = ChannelMultipliersQ12(coef.data(), terms, scale.data(), k.data());
    ASSERT_GE(shift, 0);
    ASSERT_LE(shift, kMaxRecombineShift);
    int64_t max_k = 0;
    double max_real = 0, max_err = 0;
    for (int i = 0; i < terms * 3; ++i) {
      max_k = std::max<int64_t>(max_k, std::llabs(k[i]));
      const double real = static_cast<double>(coef[i / 3]) / 65536.0 * testing::ScaleValue(scale[i]) * kQ12;
      max_real = std::max(max_real, std::fabs(real));
      max_err = std::max(max_err, std::fabs(std::ldexp(double(k[i]), -shift) - real));
    }
    // The vector path of RecombineQ12 takes |k| < 2^24; the shift uses that range.
    EXPECT_LT(max_k, int64_t{1} << 24);
    if (shift < kMaxRecombineShift) {
      EXPECT_GE(max_k, int64_t{1} << 23);
    }
    EXPECT_LE(max_err, std::ldexp(max_real, -23));
  }
}

TEST(Weights, ChannelMultipliersSaturateWhenEvenShiftZeroCannotFit) {
  const int64_t coef[1] = {int64_t{1} << 50};  // 2^34 cd
  const QuantScale scale[3] = {{1 << 29, 40}, {0, 0}, {-(1 << 29), 40}};
  int32_t k[3];
  EXPECT_EQ(ChannelMultipliersQ12(coef, 1, scale, k), 0);
  EXPECT_EQ(k[0], std::numeric_limits<int32_t>::max());
  EXPECT_EQ(k[1], 0);
  EXPECT_EQ(k[2], -std::numeric_limits<int32_t>::max());
  const int64_t zero[1] = {0};
  EXPECT_EQ(ChannelMultipliersQ12(zero, 1, scale, k), kMaxRecombineShift);
  EXPECT_EQ(k[0] | k[1] | k[2], 0);
}

}  // namespace
}  // namespace relight
