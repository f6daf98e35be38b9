// Integer elementary functions (runtime/base/src/fixed_math.cc) against exact
// integer checks and long-double references, with tolerances in LSB.
#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace relight {
namespace {

__extension__ typedef unsigned __int128 u128;

constexpr long double kPiL = 3.141592653589793238462643383279502884L;
constexpr long double kTwo32 = 4294967296.0L;

void ExpectFloorSqrt64(uint64_t v) {
  const uint64_t r = ISqrt64(v);
  ASSERT_LE(static_cast<u128>(r) * r, v) << v;
  ASSERT_GT((static_cast<u128>(r) + 1) * (r + 1), v) << v;
}

void ExpectFloorSqrt128(u128 v) {
  const uint64_t r = ISqrt128(v);
  // (r+1)^2 may need 129 bits when r = 2^64 - 1: compare r^2 <= v and
  // v - r^2 <= 2r (equivalent to v < (r+1)^2).
  const u128 r2 = static_cast<u128>(r) * r;
  ASSERT_LE(r2, v);
  ASSERT_LE(v - r2, 2 * static_cast<u128>(r));
}

// The saturating helpers (fixed_ops.h) against the plain wide arithmetic
// they replace: the exact sum, difference or value, clamped to int64.
int64_t Clamp64(Int128 v) {
  const Int128 lo = std::numeric_limits<int64_t>::min(), hi = std::numeric_limits<int64_t>::max();
  return static_cast<int64_t>(v < lo ? lo : (v > hi ? hi : v));
}

TEST(Saturate, AddSubAndNarrowMatchTheClampedWideValues) {
  constexpr int64_t kMin = std::numeric_limits<int64_t>::min(), kMax = std::numeric_limits<int64_t>::max();
  std::vector<int64_t> values = {kMin, kMin + 1, kMin / 2, -(int64_t{1} << 32), -2, -1, 0, 1, 2,
                                 int64_t{1} << 32, kMax / 2, kMax - 1, kMax};
  std::mt19937_64 rng(7);
  for (int i = 0; i < 200; ++i) values.push_back(static_cast<int64_t>(rng()) >> (rng() % 64));
  int saturated = 0;
  for (int64_t a : values) {
    for (int64_t b : values) {
      const Int128 sum = static_cast<Int128>(a) + b, diff = static_cast<Int128>(a) - b;
      ASSERT_EQ(AddSat64(a, b), Clamp64(sum)) << a << " + " << b;
      ASSERT_EQ(SubSat64(a, b), Clamp64(diff)) << a << " - " << b;
      // Wide values on both sides of the int64 range, up to +-2^126.
      const Int128 wide = static_cast<Int128>(a) * (b >> 1);
      ASSERT_EQ(SaturateI64(wide), Clamp64(wide)) << a << " x " << (b >> 1);
      ASSERT_EQ(SaturateI64(sum), Clamp64(sum));
      saturated += Clamp64(sum) != sum ? 1 : 0;
    }
  }
  EXPECT_GT(saturated, 100);  // the edges were reached
}

// RoundShiftSat64 against the plain formula: a right shift rounds halves up
// (floor((v + 2^(n-1)) / 2^n)), a left shift saturates, and zero stays zero
// at every shift (the right shifts no longer test for it).
TEST(Saturate, RoundShiftMatchesTheRoundedClampedFormula) {
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  std::mt19937_64 rng(11);
  std::vector<Int128> values = {0, 1, -1, 2, -2, 3, -3, static_cast<Int128>(kMax), -static_cast<Int128>(kMax) - 1};
  for (int i = 0; i < 400; ++i) {
    const Int128 hi = static_cast<Int128>(static_cast<int64_t>(rng()) >> (rng() % 64));
    values.push_back(hi * (Int128{1} << (rng() % 62)) + static_cast<int64_t>(rng() >> 1));
  }
  for (const Int128 v : values) {
    for (const int64_t n : {1, 2, 15, 16, 23, 24, 32, 40, 63, 64, 100, 126, 127, 130}) {
      Int128 want = 0;
      if (n < 127) want = (v + (Int128{1} << (n - 1))) >> n;  // floor: arithmetic shift
      ASSERT_EQ(RoundShiftSat64(v, -n), Clamp64(want)) << static_cast<double>(v) << " >> " << n;
    }
    for (const int64_t s : {0, 1, 16, 62, 63, 70}) {
      const int64_t got = RoundShiftSat64(v, s);
      if (v == 0) {
        ASSERT_EQ(got, 0) << "0 << " << s;
      } else if (s < 63 && static_cast<double>(v < 0 ? -v : v) * std::ldexp(1.0, static_cast<int>(s)) < 0x1p62) {
        ASSERT_EQ(static_cast<Int128>(got), v * (Int128{1} << s)) << static_cast<double>(v) << " << " << s;
      } else if (s >= 63 || static_cast<double>(v < 0 ? -v : v) * std::ldexp(1.0, static_cast<int>(s)) >= 0x1p64) {
        ASSERT_EQ(got, v > 0 ? kMax : std::numeric_limits<int64_t>::min()) << static_cast<double>(v) << " << " << s;
      }
    }
  }
}

TEST(ISqrt, ExactFloorOnEdgeCases) {
  EXPECT_EQ(ISqrt64(0), 0u);
  EXPECT_EQ(ISqrt64(1), 1u);
  EXPECT_EQ(ISqrt64(2), 1u);
  EXPECT_EQ(ISqrt64(3), 1u);
  EXPECT_EQ(ISqrt64(4), 2u);
  EXPECT_EQ(ISqrt64(UINT64_MAX), 0xFFFFFFFFu);
  EXPECT_EQ(ISqrt64(uint64_t{0xFFFFFFFE00000001}), 0xFFFFFFFFu);  // (2^32-1)^2
  EXPECT_EQ(ISqrt64(uint64_t{0xFFFFFFFE00000000}), 0xFFFFFFFEu);  // one below
  EXPECT_EQ(ISqrt128(0), 0u);
  EXPECT_EQ(ISqrt128(~static_cast<u128>(0)), UINT64_MAX);
  const u128 big = static_cast<u128>(UINT64_MAX) * UINT64_MAX;
  EXPECT_EQ(ISqrt128(big), UINT64_MAX);
  EXPECT_EQ(ISqrt128(big - 1), UINT64_MAX - 1);
  for (uint64_t k = 1; k < 70000; k += 7) {
    EXPECT_EQ(ISqrt64(k * k), k);
    EXPECT_EQ(ISqrt64(k * k - 1), k - 1);
    EXPECT_EQ(ISqrt64(k * k + 2 * k), k);  // (k+1)^2 - 1
  }
  for (int b = 0; b < 64; ++b) {
    ExpectFloorSqrt64(uint64_t{1} << b);
    ExpectFloorSqrt64((uint64_t{1} << b) - 1);
  }
  for (int b = 0; b < 128; ++b) {
    ExpectFloorSqrt128(static_cast<u128>(1) << b);
    ExpectFloorSqrt128((static_cast<u128>(1) << b) - 1);
  }
}

TEST(ISqrt, ExactFloorOnRandomValues) {
  std::mt19937_64 rng(1);
  for (int i = 0; i < 200000; ++i) {
    const uint64_t v = rng() >> (rng() % 64);
    ExpectFloorSqrt64(v);
    const u128 w = (static_cast<u128>(rng()) << 64 | rng()) >> (rng() % 128);
    ExpectFloorSqrt128(w);
    // Squares of random roots and their neighbours.
    const uint64_t r = rng() >> 32;
    EXPECT_EQ(ISqrt64(r * r), r);
    const uint64_t s = rng();
    EXPECT_EQ(ISqrt128(static_cast<u128>(s) * s), s);
    if (s > 0) {
      EXPECT_EQ(ISqrt128(static_cast<u128>(s) * s - 1), s - 1);
    }
  }
}

TEST(Angles, DegreesToBamIsRoundedAndWraps) {
  EXPECT_EQ(DegreesToBam(Q16_16::FromInt(0)), 0u);
  EXPECT_EQ(DegreesToBam(Q16_16::FromInt(45)), 0x20000000u);
  EXPECT_EQ(DegreesToBam(Q16_16::FromInt(90)), 0x40000000u);
  EXPECT_EQ(DegreesToBam(Q16_16::FromInt(180)), 0x80000000u);
  EXPECT_EQ(DegreesToBam(Q16_16::FromInt(-90)), 0xC0000000u);
  EXPECT_EQ(DegreesToBam(Q16_16::FromInt(360)), 0u);
  EXPECT_EQ(DegreesToBam(Q16_16::FromInt(450)), 0x40000000u);
  EXPECT_EQ(DegreesToBam(Q16_16::FromInt(-540)), 0x80000000u);
  EXPECT_EQ(DegreesToBam(Q16_16::FromInt(1)), 11930465u);  // 2^32/360 = 11930464.71
  std::mt19937_64 rng(2);
  for (int i = 0; i < 100000; ++i) {
    const int32_t raw = static_cast<int32_t>(rng());
    const long double exact = static_cast<long double>(raw) / 65536.0L / 360.0L * kTwo32;
    const long double rounded = std::floor(exact + 0.5L);
    const uint32_t expected =
        static_cast<uint32_t>(static_cast<uint64_t>(static_cast<int64_t>(rounded)));
    ASSERT_EQ(DegreesToBam(Q16_16::FromRaw(raw)), expected) << raw;
  }
}

TEST(Angles, BamToDegreesIsInMinus180To180) {
  EXPECT_EQ(BamToDegrees(0).raw(), 0);
  EXPECT_EQ(BamToDegrees(0x40000000u).raw(), 90 * 65536);
  EXPECT_EQ(BamToDegrees(0x80000000u).raw(), 180 * 65536);
  EXPECT_EQ(BamToDegrees(0x80000001u).raw(), 180 * 65536);  // -179.99999992 rounds to -180 -> +180
  EXPECT_EQ(BamToDegrees(0xC0000000u).raw(), -90 * 65536);
  std::mt19937_64 rng(3);
  for (int i = 0; i < 100000; ++i) {
    const uint32_t bam = static_cast<uint32_t>(rng());
    const int32_t deg = BamToDegrees(bam).raw();
    ASSERT_GT(deg, -180 * 65536);
    ASSERT_LE(deg, 180 * 65536);
    const long double exact = static_cast<long double>(static_cast<int32_t>(bam)) * 360.0L / kTwo32;
    const long double err = deg / 65536.0L - exact;
    const long double wrapped = err - 360.0L * std::round(err / 360.0L);
    ASSERT_LE(std::fabs(wrapped) * 65536.0L, 0.5L + 1e-9L) << bam;
    // Round trip through degrees: Q16.16 degrees are coarser than BAMs (1 deg
    // LSB = 182 BAM), so back within half of that.
    const int32_t back = static_cast<int32_t>(DegreesToBam(BamToDegrees(bam)) - bam);
    ASSERT_LE(std::abs(back), 92) << bam;
  }
}

TEST(SinCos, WithinTwoLsbOfDouble) {
  std::vector<uint32_t> angles;
  for (uint64_t a = 0; a < (uint64_t{1} << 32); a += 4093)
    angles.push_back(static_cast<uint32_t>(a));
  for (uint32_t k = 0; k < 16; ++k) {  // octant and quadrant boundaries, and their neighbours
    const uint32_t b = k << 28;
    angles.push_back(b);
    angles.push_back(b + 1);
    angles.push_back(b - 1);
  }
  std::mt19937_64 rng(4);
  for (int i = 0; i < 200000; ++i) angles.push_back(static_cast<uint32_t>(rng()));
  long double worst = 0;
  for (uint32_t a : angles) {
    Q1_30 s, c;
    SinCosQ30(a, &s, &c);
    const long double rad = static_cast<long double>(a) * 2 * kPiL / kTwo32;
    const long double es = std::fabs(s.raw() - std::sin(rad) * 1073741824.0L);
    const long double ec = std::fabs(c.raw() - std::cos(rad) * 1073741824.0L);
    worst = std::max(worst, std::max(es, ec));
    ASSERT_LE(es, 2.0L) << a;
    ASSERT_LE(ec, 2.0L) << a;
  }
  std::cout << "[ measured ] SinCosQ30 max error " << static_cast<double>(worst)
            << " LSB of Q1.30 over " << angles.size() << " angles\n";
  Q1_30 s, c;
  SinCosQ30(0, &s, &c);
  EXPECT_EQ(s.raw(), 0);
  EXPECT_EQ(c.raw(), 1 << 30);
  SinCosQ30(0x40000000u, &s, &c);
  EXPECT_EQ(s.raw(), 1 << 30);
  EXPECT_EQ(c.raw(), 0);
}

// Signed BAM difference between a result and the exact long-double angle.
long double BamError(uint32_t got, long double y, long double x) {
  const long double exact = std::atan2(y, x) / (2 * kPiL) * kTwo32;
  long double err = static_cast<long double>(got) - exact;
  err -= kTwo32 * std::round(err / kTwo32);
  return err;
}

// Largest |error| in BAM of an atan2 over the int64 edge cases, 300000 random
// pairs at every scale and `extra` pairs; fails at the first beyond `bound`.
template <typename Atan2>
long double MaxAtan2Error(Atan2 atan2, long double bound, uint64_t seed,
                          const std::vector<std::pair<int64_t, int64_t>>& extra = {}) {
  std::mt19937_64 rng(seed);
  long double worst = 0;
  auto check = [&](int64_t y, int64_t x) {
    const long double err =
        std::fabs(BamError(atan2(y, x), static_cast<long double>(y), static_cast<long double>(x)));
    worst = std::max(worst, err);
    EXPECT_LE(err, bound) << y << ", " << x;
    return err <= bound;
  };
  constexpr int64_t kMin = std::numeric_limits<int64_t>::min();
  constexpr int64_t kMax = std::numeric_limits<int64_t>::max();
  const int64_t edges[] = {kMin, kMin + 1, -1000000007, -3, -2, -1, 0, 1, 2, 3, 1000000007, kMax};
  for (int64_t y : edges)
    for (int64_t x : edges)
      if ((x != 0 || y != 0) && !check(y, x)) return worst;
  for (int i = 0; i < 300000; ++i) {
    const int shift = static_cast<int>(rng() % 63);
    const int64_t y = static_cast<int64_t>(rng()) >> shift;
    const int64_t x =
        static_cast<int64_t>(rng()) >> (i % 3 == 0 ? static_cast<int>(rng() % 63) : shift);
    if ((x != 0 || y != 0) && !check(y, x)) return worst;
  }
  for (const auto& [y, x] : extra)
    if (!check(y, x)) return worst;
  return worst;
}

TEST(Atan2, WithinOneBamOfDouble) {
  const long double worst = MaxAtan2Error(Atan2Bam, 1.0L, 5);
  std::cout << "[ measured ] Atan2Bam max error " << static_cast<double>(worst)
            << " BAM (1 BAM = " << 360.0 / 4294967296.0 << " deg)\n";
  EXPECT_EQ(Atan2Bam(0, 5), 0u);
  EXPECT_EQ(Atan2Bam(5, 0), 0x40000000u);
  EXPECT_EQ(Atan2Bam(0, -5), 0x80000000u);
  EXPECT_EQ(Atan2Bam(-5, 0), 0xC0000000u);
  EXPECT_EQ(Atan2Bam(7, 7), 0x20000000u);
  EXPECT_EQ(Atan2Bam(-7, -7), 0xA0000000u);
}

// The table atan2 used per vertex: every octant, every scale, the axes and
// diagonals, against the long-double angle and within the documented bound;
// densely near the table's worst point (tan = 1/sqrt(3), 30 degrees).
TEST(Atan2, FastTableWithinItsBound) {
  std::vector<std::pair<int64_t, int64_t>> near_30;
  for (int64_t i = -20000; i <= 20000; ++i) near_30.push_back({577350269 + i * 37, 1000000000});
  const long double worst = MaxAtan2Error(Atan2BamFast, kAtan2FastMaxErrorBam, 11, near_30);
  std::cout << "[ measured ] Atan2BamFast max error " << static_cast<double>(worst) << " BAM\n";
  EXPECT_EQ(Atan2BamFast(0, 5), 0u);
  EXPECT_EQ(Atan2BamFast(5, 0), 0x40000000u);
  EXPECT_EQ(Atan2BamFast(-5, 0), 0xC0000000u);
  EXPECT_EQ(Atan2BamFast(7, 7), 0x20000000u);
  EXPECT_EQ(Atan2BamFast(-7, -7), 0xA0000000u);
}

TEST(Atan2, InvertsSinCos) {
  // Q1.30 sin/cos carry ~0.5 LSB each, i.e. ~0.5/2^30 rad = 0.34 BAM.
  std::mt19937_64 rng(6);
  for (int i = 0; i < 100000; ++i) {
    const uint32_t a = static_cast<uint32_t>(rng());
    Q1_30 s, c;
    SinCosQ30(a, &s, &c);
    const int32_t diff = static_cast<int32_t>(Atan2Bam(s.raw(), c.raw()) - a);
    ASSERT_LE(std::abs(diff), 2) << a;
  }
}

TEST(Normalise, WithinHalfLsbOfDouble) {
  std::mt19937_64 rng(7);
  long double worst = 0;
  auto check = [&](const int64_t v[3]) {
    int32_t out[3];
    NormaliseQ30(v, out);
    const long double x = v[0], y = v[1], z = v[2];
    const long double n = std::sqrt(x * x + y * y + z * z);
    const long double comps[3] = {x, y, z};
    for (int i = 0; i < 3; ++i) {
      const long double err = std::fabs(out[i] - comps[i] / n * 1073741824.0L);
      worst = std::max(worst, err);
      ASSERT_LE(err, 0.5L + 1e-4L) << v[0] << " " << v[1] << " " << v[2];
    }
  };
  constexpr int64_t kMin = std::numeric_limits<int64_t>::min();
  const int64_t cases[][3] = {{1, 0, 0},          {0, 0, -5},         {kMin, 0, 0},
                              {kMin, kMin, kMin}, {3, 4, 12},         {1, 1, 1},
                              {-1, 2, -3},        {INT64_MAX, 1, -1}, {0, 1, kMin}};
  for (const auto& v : cases) check(v);
  for (int i = 0; i < 200000; ++i) {
    const int shift = static_cast<int>(rng() % 63);
    const int64_t v[3] = {static_cast<int64_t>(rng()) >> shift,
                          static_cast<int64_t>(rng()) >> shift,
                          static_cast<int64_t>(rng()) >> shift};
    if (v[0] == 0 && v[1] == 0 && v[2] == 0) continue;
    check(v);
  }
  std::cout << "[ measured ] NormaliseQ30 max error " << static_cast<double>(worst) << " LSB\n";
  int32_t out[3];
  const int64_t axis[3] = {0, 0, 42};
  NormaliseQ30(axis, out);
  EXPECT_EQ(out[0], 0);
  EXPECT_EQ(out[1], 0);
  EXPECT_EQ(out[2], 1 << 30);
}

}  // namespace
}  // namespace relight
