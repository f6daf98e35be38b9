// Fixed-point point-to-polygon form factor (point_polygon_factor.h).
//
// Scaling and overflow: corners and x Q16.16 metres, differences < 2^33
// (any scene within +-32 km). Heights n.r: Q1.30 x Q16.16 < 2^64 in Int128;
// the crossing parameter t = h_a / (h_a - h_b) at Q.32 (h << 32 < 2^96); the
// corners relative to x, r, at Q.32 (< 2^49), a crossing's (b - a) t <
// 2^66. Per edge c = r0 x r1 and d = r0 . r1 are < 2^99; both are shifted
// right together until below 2^30, so c.c < 2^62 for ISqrt64, n . c < 2^62,
// and the angle atan2(|c|, d) keeps its ratio. The angle is a binary angle (2^32 = 2 pi) in
// [0, 2^31], the cosine n . c / |c| Q1.30: their product < 2^61, summed over
// <= 16 edges in Int128. F = sum angle_rad cos / (2 pi) = sum bam cos / 2^32,
// so F in UQ0.32 is the sum shifted right by 30.
#include "point_polygon_factor.h"

#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

Int128 Height(const int32_t n_q30[3], const int64_t r[3]) {
  return static_cast<Int128>(n_q30[0]) * r[0] + static_cast<Int128>(n_q30[1]) * r[1] +
         static_cast<Int128>(n_q30[2]) * r[2];
}

}  // namespace

uint32_t PointToPolygonFactorQ32(const int64_t x_q16[3], const int32_t n_q30[3],
                                 const int64_t (*poly_q16)[3], int count) {
  if (count < 3 || count > kMaxFactorPolygonCorners) return 0;
  // Corners relative to x, clipped to n . r >= 0 (Sutherland-Hodgman), kept
  // at Q.32: a crossing rounded to Q16.16 would move by 8 um, a large angle
  // seen from a point a few millimetres away.
  int64_t r[kMaxFactorPolygonCorners + 2][3];
  int m = 0;
  for (int k = 0; k < count; ++k) {
    int64_t a[3], b[3];
    for (int i = 0; i < 3; ++i) {
      a[i] = poly_q16[k][i] - x_q16[i];
      b[i] = poly_q16[(k + 1) % count][i] - x_q16[i];
    }
    const Int128 ha = Height(n_q30, a), hb = Height(n_q30, b);
    if (ha >= 0) {
      if (m > kMaxFactorPolygonCorners) return 0;  // cannot happen for a convex polygon
      for (int i = 0; i < 3; ++i) r[m][i] = a[i] * (int64_t{1} << 16);
      ++m;
    }
    if ((ha >= 0) != (hb >= 0)) {
      if (m > kMaxFactorPolygonCorners) return 0;
      // The crossing a + (b - a) t, t = ha / (ha - hb) in [0, 1] at Q.32.
      // |h_a| x 2^32 as a product: a left shift of a negative value is undefined.
      const Int128 t = DivRound((ha < 0 ? -ha : ha) * (static_cast<Int128>(1) << 32), ha < 0 ? hb - ha : ha - hb);
      for (int i = 0; i < 3; ++i)
        r[m][i] = a[i] * (int64_t{1} << 16) + static_cast<int64_t>(RoundShift(static_cast<Int128>(b[i] - a[i]) * t, 16));
      ++m;
    }
  }
  if (m < 3) return 0;
  Int128 sum = 0;
  for (int k = 0; k < m; ++k) {
    const int64_t* r0 = r[k];
    const int64_t* r1 = r[(k + 1) % m];
    Int128 c[3] = {static_cast<Int128>(r0[1]) * r1[2] - static_cast<Int128>(r0[2]) * r1[1],
                   static_cast<Int128>(r0[2]) * r1[0] - static_cast<Int128>(r0[0]) * r1[2],
                   static_cast<Int128>(r0[0]) * r1[1] - static_cast<Int128>(r0[1]) * r1[0]};
    Int128 d = static_cast<Int128>(r0[0]) * r1[0] + static_cast<Int128>(r0[1]) * r1[1] +
               static_cast<Int128>(r0[2]) * r1[2];
    UInt128 big = Abs128(d);
    for (int i = 0; i < 3; ++i)
      if (Abs128(c[i]) > big) big = Abs128(c[i]);
    // Below 2^30 the squares' sum fits 63 bits (ISqrt64) and every product
    // after it fits int64; 30 significant bits keep the angle to ~1e-9.
    const int shift = BitLength128(big) > 30 ? BitLength128(big) - 30 : 0;
    const int64_t cx = static_cast<int64_t>(c[0] >> shift), cy = static_cast<int64_t>(c[1] >> shift),
                  cz = static_cast<int64_t>(c[2] >> shift), dd = static_cast<int64_t>(d >> shift);
    const uint32_t length = ISqrt64(static_cast<uint64_t>(cx * cx + cy * cy + cz * cz));
    if (length == 0) continue;  // x on this edge's line: it subtends no angle
    const Bam angle = Atan2BamFast(length, dd);
    // n . c / |c|: Q1.30 x 2^30 / 2^30 -> Q1.30.
    const int64_t nc = int64_t{n_q30[0]} * cx + int64_t{n_q30[1]} * cy + int64_t{n_q30[2]} * cz;
    sum += static_cast<Int128>(angle) * (nc / static_cast<int64_t>(length));
  }
  const UInt128 f = Abs128(sum) >> 30;
  return f >= (static_cast<UInt128>(1) << 32) ? 0xFFFFFFFFu : static_cast<uint32_t>(f);
}

}  // namespace relight
