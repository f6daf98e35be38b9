// Integer square roots, sin/cos and atan2 on binary angles (fixed_math.h).
//
// sin/cos: exact octant reduction of the binary angle, then Taylor series on
// [0, pi/4] at Q2.61 (Horner form, 10 terms: the first dropped term is below
// 2^-62), rounded once to Q1.30. atan2: CORDIC vectoring at ~2^60 scale with
// a compile-time table of atan(2^-i) derived from integer series, so the
// result rounds once to the BAM. No float anywhere.
#include "relight/base/fixed_math.h"

#include <array>

#include "relight/base/fixed_ops.h"

namespace relight {
namespace {


constexpr int kTaylorTerms = 10;

// sin(x), x in [0, pi/4], Q2.61: x (1 - x^2/(2*3) (1 - x^2/(4*5) (...))).
int64_t SinSmallQ61(int64_t x_q61) {
  const Int128 x2 = RoundShift(static_cast<Int128>(x_q61) * x_q61, 61);
  Int128 t = kOneQ61;
  for (int k = kTaylorTerms; k >= 1; --k) {
    t = kOneQ61 - DivRound(RoundShift(x2 * t, 61), (2 * k) * (2 * k + 1));
  }
  return static_cast<int64_t>(RoundShift(x_q61 * t, 61));
}

// cos(x), x in [0, pi/4], Q2.61: 1 - x^2/(1*2) (1 - x^2/(3*4) (...)).
int64_t CosSmallQ61(int64_t x_q61) {
  const Int128 x2 = RoundShift(static_cast<Int128>(x_q61) * x_q61, 61);
  Int128 t = kOneQ61;
  for (int k = kTaylorTerms; k >= 1; --k) {
    t = kOneQ61 - DivRound(RoundShift(x2 * t, 61), (2 * k - 1) * (2 * k));
  }
  return static_cast<int64_t>(t);
}

// --- CORDIC table: atan(2^-i) in BAM units with 16 extra fraction bits.
constexpr int kCordicSteps = 40;
constexpr int kAngleFrac = 16;

// atan(2^-i) in Q62 by its alternating series (every power of 2^-i is exact).
constexpr Int128 AtanPow2Q62(int i) {
  Int128 sum = 0;
  for (int n = 0;; ++n) {
    const int exponent = 62 - i * (2 * n + 1);
    if (exponent < 0) break;
    const Int128 term = DivRound(static_cast<Int128>(1) << exponent, 2 * n + 1);
    sum += (n % 2 == 0) ? term : -term;
  }
  return sum;
}

constexpr std::array<int64_t, kCordicSteps> MakeAtanTable() {
  std::array<int64_t, kCordicSteps> table{};
  table[0] = int64_t{1} << (29 + kAngleFrac);  // 45 degrees = 2^29 BAM, exactly
  for (int i = 1; i < kCordicSteps; ++i) {
    // BAM = rad * 2^31 / pi; with kPiQ61 and a Q62 angle: q62 * 2^(30+frac) / kPiQ61.
    table[i] = static_cast<int64_t>(
        DivRound(AtanPow2Q62(i) * (static_cast<Int128>(1) << (30 + kAngleFrac)), kPiQ61));
  }
  return table;
}

constexpr std::array<int64_t, kCordicSteps> kAtanTable = MakeAtanTable();

constexpr int HighestBit(uint64_t v) { return 63 - __builtin_clzll(v); }

// CORDIC vectoring of (x, y), 0 <= x, y < 2^60, not both 0: atan(y/x) in BAM
// with kAngleFrac extra fraction bits (the CORDIC gain 1.65 * sqrt(2) keeps
// the rotated vector below 2^62).
constexpr int64_t CordicFirstQuadrant(int64_t cx, int64_t cy) {
  int64_t z = 0;
  for (int i = 0; i < kCordicSteps; ++i) {
    const int64_t dx = cy >> i, dy = cx >> i;
    if (cy > 0) {
      cx += dx;
      cy -= dy;
      z += kAtanTable[i];
    } else {
      cx -= dx;
      cy += dy;
      z -= kAtanTable[i];
    }
  }
  return z;
}

// --- Atan2BamFast: atan(t) for t = i / 4096, i = 0..4096, in BAM
// (0 .. 2^29 = 45 degrees), rounded; built at compile time by the CORDIC
// above. Linear interpolation between entries is within h^2/8 * max|atan''|
// = 2^-24 / 8 * 0.65 rad = 3.3 BAM of the exact angle, plus two roundings
// of half a BAM: within 5 BAM (measured 4.3).
constexpr int kAtanSegmentBits = 12;
constexpr int kAtanSegments = 1 << kAtanSegmentBits;

constexpr std::array<uint32_t, kAtanSegments + 1> MakeAtanRatioTable() {
  std::array<uint32_t, kAtanSegments + 1> table{};
  for (int i = 0; i <= kAtanSegments; ++i) {
    const int64_t x = int64_t{1} << 59;
    const int64_t y = static_cast<int64_t>(i) << (59 - kAtanSegmentBits);
    const int64_t z = i == 0 ? 0 : CordicFirstQuadrant(x, y);
    table[i] = static_cast<uint32_t>(RoundShift(z, kAngleFrac));
  }
  return table;
}

constexpr std::array<uint32_t, kAtanSegments + 1> kAtanRatioTable = MakeAtanRatioTable();

// ceil(16 * sqrt(m + 1)) for m = 0..255: a start for Newton's square root
// that is never below the root.
constexpr uint64_t CeilSqrtConst(uint64_t v) {
  uint64_t r = 0;
  while (r * r < v) ++r;
  return r;
}

constexpr std::array<uint16_t, 256> MakeSqrtStartTable() {
  std::array<uint16_t, 256> table{};
  for (uint64_t m = 0; m < 256; ++m) table[m] = static_cast<uint16_t>(CeilSqrtConst(256 * (m + 1)));
  return table;
}

constexpr std::array<uint16_t, 256> kSqrtStart = MakeSqrtStartTable();

}  // namespace

void SinCosTurnQ61(uint64_t num, uint64_t den, int64_t* sin_q61, int64_t* cos_q61) {
  num %= den;
  const uint64_t eighths = num * 8;  // < 2^35
  const uint64_t octant = eighths / den;
  uint64_t rest = eighths % den;      // angle within the octant = rest/den * pi/4
  if (octant & 1) rest = den - rest;  // odd octants measure from the next multiple of pi/4
  const int64_t x =
      static_cast<int64_t>(DivRound(static_cast<Int128>(rest) * kPiQ61, 4 * static_cast<Int128>(den)));
  const int64_t s = SinSmallQ61(x), c = CosSmallQ61(x);
  switch (octant) {
    case 0:
      *sin_q61 = s;
      *cos_q61 = c;
      break;
    case 1:
      *sin_q61 = c;
      *cos_q61 = s;
      break;
    case 2:
      *sin_q61 = c;
      *cos_q61 = -s;
      break;
    case 3:
      *sin_q61 = s;
      *cos_q61 = -c;
      break;
    case 4:
      *sin_q61 = -s;
      *cos_q61 = -c;
      break;
    case 5:
      *sin_q61 = -c;
      *cos_q61 = -s;
      break;
    case 6:
      *sin_q61 = -c;
      *cos_q61 = s;
      break;
    default:
      *sin_q61 = -s;
      *cos_q61 = c;
      break;
  }
}

namespace {

// Digit-by-digit (binary restoring) square root: exact floor, for any
// unsigned width; `top` is the highest even power of two the type holds.
template <typename U>
U ISqrtFloor(U v, U top) {
  U rem = v, root = 0, bit = top;
  while (bit > v) bit >>= 2;
  while (bit != 0) {
    if (rem >= root + bit) {
      rem -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
    bit >>= 2;
  }
  return root;
}

}  // namespace

uint32_t ISqrt64(uint64_t v) {
  if (v < 2) return static_cast<uint32_t>(v);
  // v = m * 2^e (+ lower bits), e even, m < 256: sqrt(v) < sqrt(m + 1) * 2^(e/2)
  // <= kSqrtStart[m] * 2^(e/2 - 4), an over-estimate good to ~1 %. Newton's
  // step from above decreases monotonically to floor(sqrt(v)) (3-4 steps).
  const int b = HighestBit(v);
  const int e = b < 8 ? 0 : ((b - 7) + 1) & ~1;
  const uint64_t m = v >> e;
  uint64_t x = ((static_cast<uint64_t>(kSqrtStart[m]) << (e / 2)) + 15) >> 4;
  if (x > 0xFFFFFFFFu) x = 0xFFFFFFFFu;  // the root of any uint64 fits 32 bits
  for (;;) {
    const uint64_t next = (x + v / x) / 2;
    if (next >= x) return static_cast<uint32_t>(x);
    x = next;
  }
}

uint64_t ISqrt128(UInt128 v) {
  return static_cast<uint64_t>(ISqrtFloor<UInt128>(v, static_cast<UInt128>(1) << 126));
}

Bam DegreesToBam(Q16_16 degrees) {
  // BAM = deg * 2^32 / 360 = raw * 2^16 / 360 = raw * 8192 / 45, rounded.
  const int64_t num = static_cast<int64_t>(degrees.raw()) * 8192;
  // Floor division of (2 num + 45) by 90: round half up, negatives included.
  const int64_t twice = 2 * num + 45;
  int64_t q = twice / 90;
  if (twice % 90 != 0 && twice < 0) --q;
  return static_cast<Bam>(static_cast<uint64_t>(q));  // wraps modulo a turn
}

Q16_16 BamToDegrees(Bam angle) {
  if (angle == 0x80000000u) return Q16_16::FromInt(180);
  // Signed view: (-2^31, 2^31) BAM = (-180, 180) degrees; raw = s * 45 / 8192.
  const int64_t s = static_cast<int32_t>(angle);
  const int64_t twice = 2 * s * 45 + 8192;
  int64_t q = twice / 16384;
  if (twice % 16384 != 0 && twice < 0) --q;
  if (q <= -180 * 65536) q = 180 * 65536;  // rounding may land on -180: report +180
  return Q16_16::FromRaw(static_cast<int32_t>(q));
}

void SinCosQ30(Bam angle, Q1_30* sin_out, Q1_30* cos_out) {
  int64_t s = 0, c = 0;
  SinCosTurnQ61(angle, uint64_t{1} << 32, &s, &c);
  *sin_out = Q1_30::FromRaw(static_cast<int32_t>(RoundShift(s, 31)));
  *cos_out = Q1_30::FromRaw(static_cast<int32_t>(RoundShift(c, 31)));
}

namespace {

// Shifts a and b together so the larger's top bit lands on `bit` (a or b > 0).
void ScaleTopBitTo(int bit, uint64_t* a, uint64_t* b) {
  const int top = HighestBit(*a > *b ? *a : *b);
  if (top > bit) {
    *a >>= top - bit;
    *b >>= top - bit;
  } else {
    *a <<= bit - top;
    *b <<= bit - top;
  }
}

// atan2 by quadrant: the axes exactly, otherwise first_quadrant(|x|, |y|)
// (a BAM in [0, 2^30]) unfolded to the whole turn.
template <typename FirstQuadrant>
Bam Atan2ByQuadrant(int64_t y, int64_t x, FirstQuadrant first_quadrant) {
  if (y == 0) return x >= 0 ? 0u : 0x80000000u;
  if (x == 0) return y > 0 ? 0x40000000u : 0xC0000000u;
  const uint64_t ux = x < 0 ? 0 - static_cast<uint64_t>(x) : static_cast<uint64_t>(x);
  const uint64_t uy = y < 0 ? 0 - static_cast<uint64_t>(y) : static_cast<uint64_t>(y);
  const uint32_t first = first_quadrant(ux, uy);
  uint32_t bam = first;
  if (x < 0) bam = 0x80000000u - first;  // pi - a
  if (y < 0) bam = 0u - bam;             // mirror below the x axis
  return bam;
}

}  // namespace

Bam Atan2Bam(int64_t y, int64_t x) {
  return Atan2ByQuadrant(y, x, [](uint64_t ux, uint64_t uy) {
    // The larger in [2^59, 2^60): the CORDIC gain 1.65 times sqrt(2) then stays below 2^62.
    ScaleTopBitTo(59, &ux, &uy);
    const int64_t z = CordicFirstQuadrant(static_cast<int64_t>(ux), static_cast<int64_t>(uy));
    return static_cast<uint32_t>(RoundShift(z, kAngleFrac));
  });
}

Bam Atan2BamFast(int64_t y, int64_t x) {
  return Atan2ByQuadrant(y, x, [](uint64_t ux, uint64_t uy) {
    const bool steep = uy > ux;  // past 45 degrees: atan(y/x) = 90 - atan(x/y)
    uint64_t big = steep ? uy : ux, small = steep ? ux : uy;
    // big to [2^31, 2^32) (the ratio keeps 31 bits), so small * 2^32 fits 64 bits.
    ScaleTopBitTo(31, &big, &small);
    const uint64_t t = (small << 32) / big;  // tan in Q0.32, [0, 2^32]
    constexpr int kFracBits = 32 - kAtanSegmentBits;
    const uint64_t index = t >> kFracBits;
    uint32_t first = kAtanRatioTable[kAtanSegments];
    if (index < static_cast<uint64_t>(kAtanSegments)) {
      const uint64_t frac = t & ((uint64_t{1} << kFracBits) - 1);
      const uint32_t a = kAtanRatioTable[index], b = kAtanRatioTable[index + 1];
      first = a + static_cast<uint32_t>(((b - a) * frac + (uint64_t{1} << (kFracBits - 1))) >> kFracBits);
    }
    return steep ? 0x40000000u - first : first;  // [0, 2^30]
  });
}

void NormaliseQ30(const int64_t v[3], int32_t out_q30[3]) {
  // Scale so the largest |component| is in [2^49, 2^50): the squared norm fits
  // 128 bits and its square root carries ~49 significant bits.
  uint64_t mag[3];
  uint64_t largest = 0;
  for (int i = 0; i < 3; ++i) {
    mag[i] = v[i] < 0 ? 0 - static_cast<uint64_t>(v[i]) : static_cast<uint64_t>(v[i]);
    if (mag[i] > largest) largest = mag[i];
  }
  if (largest == 0) {
    out_q30[0] = out_q30[1] = out_q30[2] = 0;
    return;
  }
  const int top = HighestBit(largest);
  Int128 scaled[3];
  for (int i = 0; i < 3; ++i) {
    const uint64_t m = top > 49 ? (mag[i] >> (top - 49)) : (mag[i] << (49 - top));
    scaled[i] = v[i] < 0 ? -static_cast<Int128>(m) : static_cast<Int128>(m);
  }
  const UInt128 norm2 =
      static_cast<UInt128>(scaled[0] * scaled[0] + scaled[1] * scaled[1] + scaled[2] * scaled[2]);
  const Int128 norm = ISqrt128(norm2);
  for (int i = 0; i < 3; ++i) {
    out_q30[i] = SaturateI32(DivRound(scaled[i] * (static_cast<Int128>(1) << 30), norm));
  }
}

}  // namespace relight
