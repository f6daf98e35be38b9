// Fixed-point real SH in Cartesian form (sh_eval.h), the integer twin of the
// baker's photometry.cc:
//   Y_lm = q_l^m(z) C_m,  Y_l-m = q_l^m(z) S_m,  C_m + i S_m = (x + i y)^m,
// q_l^m a polynomial in z from normalised recurrences. No trig, no pole.
//
// Scaling and overflow: inputs Q1.30 are widened to Q3.60; C_m, S_m in Q3.60
// (|.| <= 1 for a unit vector); q_l^m in Q15.48 because q_l^m itself (without
// the sin^m factor) reaches ~950 near the poles at l = 16 and ~16900 at
// l = 22 (kMaxShDegree; Q15.48 holds 32768). Every product is
// int64 x int64 -> int128 (< 2^127), rounded back to int64 with saturation,
// so a non-unit input gives wrong numbers, never undefined behaviour. The
// Q1.30 outputs round once: error <= 1 LSB at every degree (tests measure it).
#include "relight/engine/sh_eval.h"

#include "relight/base/fixed_ops.h"
#include "relight/base/fixed_math.h"

namespace relight {
namespace {

constexpr int kQ = 48;  // fraction bits of q_l^m (Q15.48, see above)

// sqrt(num/den) in Q60, for num/den < 64, num and den < 2^32 (floor; error
// < 1 ulp of Q60).
int64_t SqrtRatioQ60(uint64_t num, uint64_t den) {
  // floor(num * 2^120 / den) without overflowing 128 bits, in two steps of
  // 2^60: the remainder is < den, so (rem << 60) < 2^92. (One step of 2^120
  // on num % den overflowed once den > 256, i.e. from degree 17 on.)
  const UInt128 hi = (static_cast<UInt128>(num) << 60) / den;  // < 2^66
  const UInt128 rem = (static_cast<UInt128>(num) << 60) % den;
  return static_cast<int64_t>(ISqrt128((hi << 60) + (rem << 60) / den));
}

int64_t MulQ60(int64_t a, int64_t b) {
  return SaturateI64(RoundShift(static_cast<Int128>(a) * b, 60));
}

// Walks the recurrence for one direction and hands each term to
// emit(t, l, y_q60), Y_t in Q3.60.
template <typename Emit>
void ForEachShQ60(const ShTables& tables, int degree, const int32_t dir_q30[3], Emit emit) {
  RELIGHT_CHECK(degree >= 0 && degree <= kMaxShDegree);
  // Q30 -> Q60 by multiplying: a left shift of a negative value is undefined
  // before C++20 (UBSan); |d| <= 2^31, so the product fits and has the same bits.
  constexpr int64_t kQ30ToQ60 = int64_t{1} << 30;
  const int64_t x = static_cast<int64_t>(dir_q30[0]) * kQ30ToQ60;
  const int64_t y = static_cast<int64_t>(dir_q30[1]) * kQ30ToQ60;
  const int64_t z = static_cast<int64_t>(dir_q30[2]) * kQ30ToQ60;
  int64_t c = kOneQ60, s = 0;  // C_m, S_m
  for (int m = 0; m <= degree; ++m) {
    if (m > 0) {
      // (x + i y)^m = (x + i y) (C_{m-1} + i S_{m-1})
      const int64_t c_next =
          SaturateI64(RoundShift(static_cast<Int128>(x) * c - static_cast<Int128>(y) * s, 60));
      s = SaturateI64(RoundShift(static_cast<Int128>(x) * s + static_cast<Int128>(y) * c, 60));
      c = c_next;
    }
    int64_t q_prev = 0;                                                         // q_{l-1}^m, Q48
    int64_t q = static_cast<int64_t>(RoundShift(tables.seed_q60[m], 60 - kQ));  // q_m^m, Q48
    for (int l = m; l <= degree; ++l) {
      if (l > m) {
        const Int128 zq = RoundShift(static_cast<Int128>(z) * q, 60);
        const Int128 bq = RoundShift(static_cast<Int128>(tables.b_q60[l][m]) * q_prev, 60);
        const int64_t diff = SaturateI64(zq - bq);
        const int64_t q_next =
            SaturateI64(RoundShift(static_cast<Int128>(tables.a_q60[l][m]) * diff, 60));
        q_prev = q;
        q = q_next;
      }
      if (m == 0) {
        emit(ShIndex(l, 0), l, SaturateI64(static_cast<Int128>(q) * (int64_t{1} << (60 - kQ))));  // Q48 -> Q60
      } else {
        emit(ShIndex(l, m), l, SaturateI64(RoundShift(static_cast<Int128>(q) * c, kQ)));
        emit(ShIndex(l, -m), l, SaturateI64(RoundShift(static_cast<Int128>(q) * s, kQ)));
      }
    }
  }
}

}  // namespace

void InitShTables(ShTables* tables) {
  *tables = ShTables{};
  // q_0^0 = sqrt(1/(4 pi)): floor(2^120 / (4 pi)) = floor(2^179 / kPiQ61), by
  // long division in two 128-bit steps.
  const UInt128 two127 = static_cast<UInt128>(1) << 127;
  const UInt128 pi = static_cast<UInt128>(kPiQ61);
  const UInt128 inv_4pi_q120 = ((two127 / pi) << 52) + (((two127 % pi) << 52) / pi);
  tables->seed_q60[0] = static_cast<int64_t>(ISqrt128(inv_4pi_q120));
  for (int m = 1; m <= kMaxShDegree; ++m) {
    // q_m^m = -sqrt((2m+1)/(2m)) q_{m-1}^{m-1}, times sqrt(2) once at m = 1:
    // -sqrt(3) q_0^0 there.
    const int64_t ratio = m == 1 ? SqrtRatioQ60(3, 1) : SqrtRatioQ60(2 * m + 1, 2 * m);
    tables->seed_q60[m] = -MulQ60(ratio, tables->seed_q60[m - 1]);
  }
  for (int l = 1; l <= kMaxShDegree; ++l) {
    for (int m = 0; m < l; ++m) {
      const uint64_t ul = static_cast<uint64_t>(l), um = static_cast<uint64_t>(m);
      // a = sqrt((4l^2-1)/(l^2-m^2)), b = sqrt(((l-1)^2-m^2)/(4(l-1)^2-1))
      tables->a_q60[l][m] = SqrtRatioQ60(4 * ul * ul - 1, ul * ul - um * um);
      tables->b_q60[l][m] =
          SqrtRatioQ60((ul - 1) * (ul - 1) - um * um, 4 * (ul - 1) * (ul - 1) - 1);
    }
  }
  for (int l = 0; l <= kMaxShDegree; ++l) {
    // 4 pi/(2l+1) in Q58 = kPiQ61 * 4 / (2l+1) / 2^3
    tables->four_pi_over_q58[l] = static_cast<int64_t>(DivRound(kPiQ61, 2 * (2 * l + 1)));
  }
}

void EvalShQ30(const ShTables& tables, int degree, const int32_t dir_q30[3], int32_t* out_q30) {
  ForEachShQ60(tables, degree, dir_q30, [out_q30](int t, int, int64_t y_q60) {
    out_q30[t] = SaturateI32(RoundShift(y_q60, 30));
  });
}

void AimCoefficientsQ30(const ShTables& tables, int degree, const int32_t aim_q30[3],
                        int64_t* out_q30) {
  // Dobashi Eq. 10: Q60 x Q58 -> Q118 (< 2^123) -> Q30.
  ForEachShQ60(tables, degree, aim_q30, [&tables, out_q30](int t, int l, int64_t y_q60) {
    out_q30[t] = SaturateI64(RoundShift(static_cast<Int128>(y_q60) * tables.four_pi_over_q58[l], 88));
  });
}

Q1_30 SigmaQ30(int degree, int l) {
  RELIGHT_CHECK(degree >= 0 && l >= 0);
  if (l == 0) return Q1_30::FromRaw(int32_t{1} << 30);
  // Dobashi Eq. 13: sin(x)/x, x = pi l/(N+1) = l/(2(N+1)) of a turn.
  int64_t sin_q61 = 0, cos_q61 = 0;
  SinCosTurnQ61(static_cast<uint64_t>(l), 2 * static_cast<uint64_t>(degree + 1), &sin_q61,
                          &cos_q61);
  // sin / x = sin_q61 (N+1) / (kPiQ61 l), in Q30.
  const Int128 num = static_cast<Int128>(sin_q61) * (degree + 1) * (static_cast<Int128>(1) << 30);
  const Int128 den = static_cast<Int128>(kPiQ61) * l;
  return Q1_30::FromRaw(SaturateI32(DivRound(num, den)));
}

}  // namespace relight
