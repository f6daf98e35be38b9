// A zoomed beam's LID samples (see zoom.h).
#include "zoom.h"

#include "relight/bake/bake_limits.h"
#include "relight/base/fixed_ops.h"
#include "relight/engine/legendre_weights.h"

namespace relight {
namespace {

constexpr int kUnitShift = 8;  // u_k = f_k (Q2.30) << 8: Q48.16 with a 2^22 cd peak
// 4 pi in Q2.30 (12.566370614359172 x 2^30, rounded).
constexpr int64_t kFourPiQ30 = 13493037705;

// f at profile position pos_q16 (samples, Q.16); 0 past the last sample.
int64_t ProfileQ30(const BakeZoom& zoom, Int128 pos_q16) {
  const int64_t last = static_cast<int64_t>(zoom.profile.size()) - 1;
  if (pos_q16 > (static_cast<Int128>(last) << 16)) return 0;
  const int64_t i = static_cast<int64_t>(pos_q16 >> 16);
  const int64_t frac = static_cast<int64_t>(pos_q16 & 0xFFFF);
  const int64_t a = zoom.profile[static_cast<size_t>(i)];
  if (i == last || frac == 0) return a;
  const int64_t b = zoom.profile[static_cast<size_t>(i + 1)];
  return a + static_cast<int64_t>(RoundShift(static_cast<Int128>(b - a) * frac, 16));
}

}  // namespace

Q16_16 ClampZoomDegrees(const BakeZoom& zoom, Q16_16 beam_deg) {
  if (beam_deg.raw() < zoom.min_deg) return Q16_16::FromRaw(zoom.min_deg);
  if (beam_deg.raw() > zoom.max_deg) return Q16_16::FromRaw(zoom.max_deg);
  return beam_deg;
}

void ZoomedLidSamplesQ16(const BakeZoom& zoom, Q16_16 beam_deg, const int32_t* sin_row_q30, int M,
                         int64_t* out) {
  // pos_k = gamma_k / (beam / 2) / x_end x (F - 1) samples
  //       = 360 k (F - 1) / (M beam x_end), beam and x_end in Q16.16, pos in Q.16.
  const Int128 den = static_cast<Int128>(M) * beam_deg.raw() * zoom.profile_end;
  const Int128 num_per_k = static_cast<Int128>(360) * (static_cast<int64_t>(zoom.profile.size()) - 1)
                           << 48;
  // pos_k = floor(k num_per_k / den), stepped without a division per sample
  // (both are positive: M, the clamped beam and profile_end are); past the
  // profile's end every further sample is 0.
  const Int128 step = num_per_k / den, step_rem = num_per_k % den;
  const Int128 end_q16 = static_cast<Int128>(zoom.profile.size() - 1) << 16;
  Int128 pos = 0, rem = 0;
  int lit = 0;
  for (; lit <= M; ++lit) {
    out[lit] = ProfileQ30(zoom, pos) << kUnitShift;
    if (pos > end_q16) break;
    pos += step;
    rem += step_rem;
    if (rem >= den) {
      pos += 1;
      rem -= den;
    }
  }
  for (; lit <= M; ++lit) out[lit] = 0;
  int64_t w0_unit_q16 = 0;  // flux / 4 pi of the unit beam (Eq. 19, l = 0)
  LegendreWeightsQ16(sin_row_q30, 0, M, out, &w0_unit_q16);
  if (w0_unit_q16 <= 0) {  // a beam narrower than the sample spacing: all light on the axis
    for (int k = 0; k <= M; ++k) out[k] = 0;
    return;
  }
  const Int128 scale_den = static_cast<Int128>(kFourPiQ30) * w0_unit_q16;
  for (int k = 0; k <= M; ++k) {
    if (out[k] == 0) continue;  // the dark samples stay 0
    const Int128 v = DivRound((static_cast<Int128>(out[k]) * zoom.lumens) << 30, scale_den);
    out[k] = v > bake_format::kMaxCandelaRaw ? bake_format::kMaxCandelaRaw : static_cast<int64_t>(v);
  }
}

}  // namespace relight
