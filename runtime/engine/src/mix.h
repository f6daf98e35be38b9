// Mixing the luminaires' cached results: out = sum over luminaires of
// dimmer * colour_c * cached light. This is all a dimmer or colour change
// costs: O(receivers x luminaires), no SH term touched.
// Integer-only, allocation-free (caller-owned spans), thread-safe.
#pragma once

#include <cstdint>

#include "relight/base/fixed.h"

namespace relight {

// Gain 1.0 in Q2.30.
inline constexpr int32_t kUnityGainQ30 = int32_t{1} << 30;

// dimmer * colour as a Q2.30 gain, with the Q1.15 full scale 32767
// (Q1_15::kOneRaw) taken as exactly 1: full on leaves the cache unscaled.
// Inputs are clamped to [0, 32767].
// Scaling and overflow: d c (< 2^30) x 2^30 in int64 (< 2^60), divided by
// 32767^2 with rounding: at most 2^30 exactly, which Q1_30 holds.
Q1_30 GainQ30(Q1_15 dimmer, Q1_15 colour);

// One luminaire's contribution: a + b (b may be null), 3 per receiver,
// LightQ12, times a per-channel gain.
struct MixSource {
  const int32_t* a = nullptr;
  const int32_t* b = nullptr;
  Q1_30 gain[3];  // Q2.30 use of Q1_30: 0 .. 2^30 (1.0)
};

// out[i] = sat32(sum_l round(gain_l[c] * (a_l[i] + b_l[i]) / 2^30)), i = r*3 + c.
//
// Scaling and overflow:
//   a, b   LightQ12 int32; a + b formed in int64 (< 2^32)
//   gain   Q1_30 holding 0 .. 2^30 (= 1.0)
//   term   < 2^62 in int64, rounded (halves up) to Q12 per luminaire
//          (<= 0.5 LSB error each), so each addend is < 2^32
//   acc    int64 over luminaires: < 2^63 for up to 2^31 luminaires
//   out    saturated to int32, never wraps.
// scratch: scratch_len >= 3 int64, used in blocks.
void MixLuminairesQ12(const MixSource* sources, uint32_t source_count, uint32_t receiver_count,
                      int64_t* scratch, uint32_t scratch_len, int32_t* out);

}  // namespace relight
