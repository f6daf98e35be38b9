// Fixture state -> per-term multipliers (see weights.h). Dobashi Eq. 18.
#include "weights.h"

#include "relight/base/fixed_math.h"
#include "relight/engine/legendre_weights.h"
#include "recombine_avx2.h"
#include "relight/base/sh_index.h"
#include "relight/base/fixed_ops.h"
#include "relight/base/status.h"

namespace relight {

void BeamAxisQ30(Mounting mounting, Q16_16 pan_deg, Q16_16 tilt_deg, int32_t axis_q30[3]) {
  Q1_30 sin_p, cos_p, sin_t, cos_t;
  SinCosQ30(DegreesToBam(pan_deg), &sin_p, &cos_p);
  SinCosQ30(DegreesToBam(tilt_deg), &sin_t, &cos_t);
  // Q1.30 x Q1.30 = Q2.60, back to Q1.30 rounded.
  const Int128 x = static_cast<Int128>(sin_t.raw()) * cos_p.raw();
  const Int128 y = static_cast<Int128>(sin_t.raw()) * sin_p.raw();
  axis_q30[0] = SaturateI32(RoundShiftSat64(x, -30));
  axis_q30[1] = SaturateI32(RoundShiftSat64(y, -30));
  axis_q30[2] = mounting == Mounting::kStanding ? cos_t.raw() : -cos_t.raw();
}

int64_t SigmaDampedQ16(int degree, int l, int64_t value_q16) {
  // Q48.16 x Q1.30 in 128 bits (< 2^94), back to Q48.16. Dobashi Eq. 12-13.
  const Int128 p = static_cast<Int128>(value_q16) * SigmaQ30(degree, l).raw();
  return RoundShiftSat64(p, -30);
}

Status DampedLegendreWeightsQ16(int degree, bool use_sigma, const int64_t* candela_q16, int M,
                                int32_t* table_scratch_q30, int64_t* damped_weights_q16) {
  RELIGHT_RETURN_IF_ERROR(BuildLegendreTableQ30(degree, M, table_scratch_q30));
  LegendreWeightsQ16(table_scratch_q30, degree, M, candela_q16, damped_weights_q16);  // Eq. 19
  if (use_sigma) {
    for (int l = 0; l <= degree; ++l) {
      damped_weights_q16[l] = SigmaDampedQ16(degree, l, damped_weights_q16[l]);
    }
  }
  return Status::Ok();
}

void TermCoefficientsQ16(const ShTables& tables, int degree, const int64_t* damped_weights_q16,
                         const int32_t axis_q30[3], int64_t* alm_scratch_q30, int64_t* coef_q16) {
  AimCoefficientsQ30(tables, degree, axis_q30, alm_scratch_q30);  // Eq. 10
  for (int l = 0; l <= degree; ++l) {
    for (int m = -l; m <= l; ++m) {
      const int t = ShIndex(l, m);
      // Q48.16 cd x Q34.30 = Q.46, back to Q48.16. Eq. 18.
      const Int128 p = static_cast<Int128>(damped_weights_q16[l]) * alm_scratch_q30[t];
      coef_q16[t] = RoundShiftSat64(p, -30);
    }
  }
}

namespace {

// The power of two applied to coef * mantissa for shift F (see weights.h),
// clamped to a range where RoundShiftSat64 is exact and no int overflows.
int64_t MultiplierExponent(int32_t exponent, int shift) {
  int64_t s = static_cast<int64_t>(exponent) - 34 + shift;
  if (s > 200) s = 200;
  if (s < -200) s = -200;
  return s;
}

}  // namespace

int ChannelMultipliersQ12(const int64_t* coef_q16, int term_count, const QuantScale* basis_scale,
                          int32_t* k_out) {
  RELIGHT_CHECK(term_count >= 0 && term_count <= ShTermCount(kMaxShDegree));
  // The recombination kernel's vector path takes |k| < 2^24 (recombine_avx2.h).
  constexpr int64_t kLimit = int64_t{1} << kVectorMultiplierBits;
  const int values = term_count * 3;
  // Each product once (a compressed basis's projection calls this on every
  // aim change: three passes over the Int128 products were 3 % of it).
  Int128 product[3 * ShTermCount(kMaxShDegree)];
  // |coef * mantissa| < 2^b gives |k| < 2^(b + exponent - 34 + F): F <= 58 - b - exponent
  // keeps that at or below 2^24.
  int64_t f = kMaxRecombineShift;
  for (int i = 0; i < values; ++i) {
    const QuantScale& s = basis_scale[i];
    const Int128 p = static_cast<Int128>(coef_q16[i / 3]) * s.mantissa;
    product[i] = p;
    if (p == 0) continue;
    const int64_t bound = 58 - BitLength128(Abs128(p)) - static_cast<int64_t>(s.exponent);
    if (bound < f) f = bound;
  }
  if (f < 0) f = 0;
  // Rounding can still reach exactly 2^24: then one bit less and again.
  for (;;) {
    bool fits = true;
    for (int i = 0; i < values; ++i) {
      int64_t k = RoundShiftSat64(product[i], MultiplierExponent(basis_scale[i].exponent, static_cast<int>(f)));
      fits = fits && k < kLimit && k > -kLimit;
      // Only when even F = 0 cannot fit 2^24 (outputs that saturate for any
      // sizeable q): keep what int32 holds; the kernel then runs its scalar path.
      constexpr int64_t kInt32Limit = int64_t{1} << 31;
      if (k >= kInt32Limit) k = kInt32Limit - 1;
      if (k <= -kInt32Limit) k = -(kInt32Limit - 1);
      k_out[i] = static_cast<int32_t>(k);
    }
    if (fits || f == 0) break;
    --f;
  }
  return static_cast<int>(f);
}

}  // namespace relight
