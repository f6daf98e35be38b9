// Zoom (bake.h BakeZoom): a full beam angle -> the LID samples of the beam at
// that angle, holding its lumens. The shape is one normalised profile f(x),
// x = gamma / (beam angle / 2), so a zoom only rescales the angle axis and
// the peak. Integer-only, allocation-free (caller-owned spans), thread-safe.
#pragma once

#include <cstdint>

#include "relight/bake/bake.h"
#include "relight/base/fixed.h"

namespace relight {

// The angle clamped to the zoom's range [min, max] (a console's zoom channel
// spans the lens's range; anything past it is the stop).
Q16_16 ClampZoomDegrees(const BakeZoom& zoom, Q16_16 beam_deg);

// out[k], k = 0..M: the beam's intensity at gamma_k = 180 k / M degrees,
// Q48.16 cd, for the full beam angle `beam_deg` (within the range), peak
// chosen so that the flux is zoom.lumens: Dobashi Eq. 19's w_0 is the flux
// over 4 pi, taken with the engine's own trapezoid rule over
// `sin_row_q30` (the Legendre table's l = 0 row, sin gamma_k in Q1.30), so
// the weights the engine derives from these samples carry exactly the lumens.
//
// Scaling and overflow: the profile position of gamma_k is
// 360 k (F-1) / (M beam x_end) in Q.16 (numerator < 2^86, in int128); f is
// interpolated in Q2.30 (|step| < 2^31 x 2^16); the unit beam u_k = f_k x 2^8
// is Q48.16 with a 2^22 cd peak; then I_k = u_k x lumens / (4 pi w_0(u)),
// formed as u (< 2^39) x lumens (<= 2^48) x 2^30 < 2^117 over 4 pi (Q1.30
// x 2^2) x w_0 (< 2^39) in int128, rounded once and saturated to
// bake_limits.h kMaxCandelaRaw.
void ZoomedLidSamplesQ16(const BakeZoom& zoom, Q16_16 beam_deg, const int32_t* sin_row_q30, int M,
                         int64_t* out);

}  // namespace relight
