// Legendre weights of a rotationally symmetric beam in fixed point
// (legendre_weights.h): the table of Dobashi Eq. 20, the trapezoid sum of
// Eq. 19 and its incremental update, Eq. 21.
//
// Scaling and overflow:
// * Table: cos, sin of gamma_k and P_l (Bonnet recurrence) in Q2.61, one
//   rounding to Q1.30 per entry (|f_l| <= 1).
// * Weights: candela Q48.16 x table Q1.30 -> Q46 products summed in int128
//   (each < 2^94, so 2^24 samples still leave > 2^6 headroom for the
//   (2l+1) <= 33 factor). The sum is then scaled by dgamma = pi/M (pi in
//   Q61, the sum pre-shifted to 63 significant bits so the product fits 127)
//   and rounded once to Q48.16, saturating.
#include "relight/engine/legendre_weights.h"

#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"
#include "relight/base/sh_index.h"

namespace relight {
namespace {


// t_k of Eq. 19/21, doubled so it stays an integer: 1 at the ends, 2 inside.
int TwiceTrapezoidWeight(int k, int M) { return (k == 0 || k == M) ? 1 : 2; }

int BitLength(UInt128 v) {
  const uint64_t hi = static_cast<uint64_t>(v >> 64), lo = static_cast<uint64_t>(v);
  if (hi != 0) return 128 - __builtin_clzll(hi);
  return lo != 0 ? 64 - __builtin_clzll(lo) : 0;
}

// round(v * dgamma / 2^32) = round(v * pi / (M * 2^32)) in Q48.16, for v in
// Q46 carrying a factor 4 (doubled t_k, and the 2 of (2l+1)/2).
// With pi = kPiQ61 / 2^61: v * kPiQ61 / (M * 2^93).
int64_t TimesDgammaQ16(Int128 v, int M) {
  const UInt128 magnitude = v < 0 ? static_cast<UInt128>(-v) : static_cast<UInt128>(v);
  int pre = BitLength(magnitude) - 63;  // keep 63 significant bits: v * pi < 2^126
  if (pre < 0) pre = 0;
  const Int128 v_short = pre > 0 ? RoundShift(v, pre) : v;
  const Int128 den = static_cast<Int128>(M) << (93 - pre);
  return SaturateI64(DivRound(v_short * kPiQ61, den));
}

}  // namespace

Status BuildLegendreTableQ30(int degree, int M, int32_t* table_q30) {
  if (M < 2)
    return Status(StatusCode::kInvalidArgument, StrFormat("legendre table: M = %d < 2", M));
  if (degree < 0 || degree > kMaxShDegree) {
    return Status(StatusCode::kInvalidArgument,
                  StrFormat("legendre table: degree %d outside [0, %d]", degree, kMaxShDegree));
  }
  for (int k = 0; k <= M; ++k) {
    // gamma_k = k pi/M = k/(2M) of a turn
    int64_t sin_q61 = 0, cos_q61 = 0;
    SinCosTurnQ61(static_cast<uint64_t>(k), 2 * static_cast<uint64_t>(M), &sin_q61,
                            &cos_q61);
    Int128 p_prev = 0, p = kOneQ61;  // P_{l-1}, P_l in Q61
    for (int l = 0; l <= degree; ++l) {
      if (l > 0) {
        // Bonnet: l P_l = (2l-1) x P_{l-1} - (l-1) P_{l-2}
        const Int128 xp = RoundShift(cos_q61 * p, 61);
        const Int128 p_next = DivRound((2 * l - 1) * xp - (l - 1) * p_prev, l);
        p_prev = p;
        p = p_next;
      }
      // Dobashi Eq. 20: P_l(cos gamma_k) sin gamma_k, Q61 x Q61 -> Q30.
      table_q30[l * (M + 1) + k] = SaturateI32(RoundShift(p * sin_q61, 92));
    }
  }
  return Status::Ok();
}

void LegendreWeightsQ16(const int32_t* table_q30, int degree, int M, const int64_t* candela_q16,
                        int64_t* weights_q16) {
  // A zoomed beam is dark past its field angle (most of the samples): its
  // zeros add nothing, so the sums stop at the last lit sample.
  int last = M;
  while (last >= 0 && candela_q16[last] == 0) --last;
  for (int l = 0; l <= degree; ++l) {
    const int32_t* row = table_q30 + l * (M + 1);
    Int128 sum = 0;  // 2 * sum_k t_k I_k f_l, Q46
    for (int k = 0; k <= last; ++k) {
      sum += static_cast<Int128>(candela_q16[k]) * row[k] * TwiceTrapezoidWeight(k, M);
    }
    // Dobashi Eq. 19: w_l = (2l+1)/2 * (sum / 2) * dgamma.
    weights_q16[l] = TimesDgammaQ16(sum * (2 * l + 1), M);
  }
}

void UpdateLegendreWeightsQ16(const int32_t* table_q30, int degree, int M, int k,
                              int64_t old_candela_q16, int64_t new_candela_q16,
                              int64_t* weights_q16) {
  RELIGHT_CHECK(k >= 0 && k <= M);
  const Int128 delta_q16 = static_cast<Int128>(new_candela_q16) - old_candela_q16;
  for (int l = 0; l <= degree; ++l) {
    // Dobashi Eq. 21 with the (2l+1)/2 of Eq. 19: t_k dI f_l dgamma (2l+1)/2.
    const Int128 step =
        delta_q16 * table_q30[l * (M + 1) + k] * TwiceTrapezoidWeight(k, M) * (2 * l + 1);
    weights_q16[l] = SaturateI64(static_cast<Int128>(weights_q16[l]) + TimesDgammaQ16(step, M));
  }
}

}  // namespace relight
