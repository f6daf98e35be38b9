// Fixture state -> per-term recombination multipliers, at control rate (a
// pan/tilt change). Dobashi Eq. 18: the weight of basis luminance t is
// sigma(N, l) w_l A_lm(aim); here it is folded with the bake's quantisation
// scale of each (term, channel) into one int32 multiplier and one shift, so
// the hot kernel (recombine.h) is a plain int16 x int32 dot product.
// Integer-only, allocation-free, thread-safe (caller-owned buffers).
#pragma once

#include <cstdint>

#include "relight/bake/bake.h"
#include "relight/base/fixed.h"
#include "relight/engine/sh_eval.h"
#include "relight/base/status.h"

namespace relight {

// Largest final shift ChannelMultipliersQ12 hands the kernel.
inline constexpr int kMaxRecombineShift = 62;

// Beam axis of a fixture as a Q1.30 unit vector (bake.h convention):
//   hanging (sin t cos p, sin t sin p, -cos t), standing (..., +cos t).
void BeamAxisQ30(Mounting mounting, Q16_16 pan_deg, Q16_16 tilt_deg, int32_t axis_q30[3]);

// sigma(N, l) x value (Dobashi Eq. 12-13): the one sigma-factor damping,
// of a Legendre weight w_l or of an SH coefficient of band l alike.
// Scaling and overflow: Q48.16 in and out; the product with sigma (Q1.30,
// 0..1) is formed in 128 bits (< 2^94) and rounded once (halves up), so the
// result never exceeds |value| and cannot overflow.
int64_t SigmaDampedQ16(int degree, int l, int64_t value_q16);

// sigma(N, l) w_l (or w_l alone when !use_sigma), l = 0..degree, Q48.16 cd,
// from the LID's M+1 samples (Dobashi Eq. 12-13, 19). Done once at Open.
// table_scratch_q30 holds (degree+1)*(M+1) entries.
// Returns kInvalidArgument if the degree or M is out of range.
Status DampedLegendreWeightsQ16(int degree, bool use_sigma, const int64_t* candela_q16, int M,
                                int32_t* table_scratch_q30, int64_t* damped_weights_q16);

// coef_t = sigma_l w_l A_lm(axis) for t < (degree+1)^2, Q48.16 cd
// (Dobashi Eq. 10, 18). alm_scratch_q30 holds (degree+1)^2 entries.
void TermCoefficientsQ16(const ShTables& tables, int degree, const int64_t* damped_weights_q16,
                         const int32_t axis_q30[3], int64_t* alm_scratch_q30, int64_t* coef_q16);

// Per (term, channel) multipliers for RecombineQ12 and the shift F they share:
//   k_tc = round(coef_t * mantissa_tc * 2^(exponent_tc - 34 + F)),
// so that sum_t q_tc * k_tc >> F is the output in LightQ12 (the 34 is the
// 30 of QuantScale plus the 16 of Q48.16 minus the 12 of LightQ12).
// F in [0, kMaxRecombineShift] is the largest shift that keeps every
// |k_tc| < 2^24 (what the kernel's vector path takes, recombine_avx2.h); if
// even F = 0 does not (an output that saturates for sizeable q), k keeps its
// value up to +-(2^31 - 1) and the kernel takes its exact scalar path.
// k_out: term_count * 3.
int ChannelMultipliersQ12(const int64_t* coef_q16, int term_count, const QuantScale* basis_scale,
                          int32_t* k_out);

}  // namespace relight
