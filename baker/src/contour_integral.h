// Lambert's contour integral for the point-to-polygon form factor, one edge at
// a time, written so that one call and a vectorised loop over many receiving
// points (polygon_factor_kernel.h) give the same bits: no branches (the
// compiler turns the selects into blends) and no library call.
//
// The edge (a, b) of a polygon seen from x adds angle(r_a, r_b) n . c / |c|,
// r = corner - x, c = r_a x r_b. The angle is atan2(|c|, r_a . r_b), here by
// EdgeAngle: glibc's atan2 is a call the loop cannot vectorise, and it was
// about a quarter of a hierarchical bake's links phase (docs/venue.md).
#pragma once

namespace relight::baker {

// atan2(y, x) for y >= 0, in [0, pi], within about 2 ulp of the exact value.
// Reduced to atan(t), t = min(y, |x|) / max(y, |x|) in [0, 1]; above 0.66,
// atan(t) = pi/4 + atan((t - 1) / (t + 1)). The rational approximation on
// |z| <= 0.66 and the split of pi/2 into a double and its remainder are
// Cephes's (S. L. Moshier, atan.c): z + z^3 P(z^2) / Q(z^2).
// y = x = 0 gives NaN (the callers leave such an edge out).
inline double EdgeAngle(double y, double x) {
  constexpr double kP0 = -8.750608600031904122785e-1, kP1 = -1.615753718733365076637e1,
                   kP2 = -7.500855792314704667340e1, kP3 = -1.228866684490136173410e2,
                   kP4 = -6.485021904942025371773e1;
  constexpr double kQ0 = 2.485846490142306297962e1, kQ1 = 1.650270098316988542046e2,
                   kQ2 = 4.328810604912902668951e2, kQ3 = 4.853903996359136964868e2,
                   kQ4 = 1.945506571482613964425e2;
  constexpr double kPiOver2 = 1.57079632679489661923, kPiOver4 = 0.785398163397448309616;
  constexpr double kPiOver2Rest = 6.123233995736765886130e-17;  // pi/2 - kPiOver2
  const double ax = x < 0 ? -x : x;
  const bool swap = y > ax;
  const double small = swap ? ax : y, big = swap ? y : ax;
  const bool upper = small > 0.66 * big;  // t > 0.66
  const double z = (upper ? small - big : small) / (upper ? small + big : big);
  const double zz = z * z;
  const double p = (((kP0 * zz + kP1) * zz + kP2) * zz + kP3) * zz + kP4;
  const double q = ((((zz + kQ0) * zz + kQ1) * zz + kQ2) * zz + kQ3) * zz + kQ4;
  double a = (z + z * (zz * p / q)) + (upper ? 0.5 * kPiOver2Rest : 0.0);
  a = (upper ? kPiOver4 : 0.0) + a;                     // atan(t)
  a = swap ? (kPiOver2 - a) + kPiOver2Rest : a;         // atan(y / |x|)
  return x < 0 ? (2 * kPiOver2 - a) + 2 * kPiOver2Rest : a;  // the angle from +x
}

// The edge term for r0 = a - x, r1 = b - x and the receiver's normal n
// (components as separate arguments so vector lanes can feed them); 0 when
// x lies on the edge's line.
inline double ContourEdgeTerm(double r0x, double r0y, double r0z, double r1x, double r1y,
                              double r1z, double nx, double ny, double nz) {
  const double cx = r0y * r1z - r0z * r1y, cy = r0z * r1x - r0x * r1z, cz = r0x * r1y - r0y * r1x;
  const double c_len = __builtin_sqrt(cx * cx + cy * cy + cz * cz);
  const double dot = r0x * r1x + r0y * r1y + r0z * r1z;
  const double n_dot_c = nx * cx + ny * cy + nz * cz;
  const double term = EdgeAngle(c_len, dot) * n_dot_c / (c_len > 0 ? c_len : 1.0);
  return c_len > 0 ? term : 0.0;
}

// The factor from the sum of a polygon's edge terms: its sign follows the
// winding as seen from x, so the magnitude over 2 pi, at most 1.
inline double FactorFromContourSum(double sum) {
  constexpr double kTwoPi = 6.28318530717958647692;
  const double f = (sum < 0 ? -sum : sum) / kTwoPi;
  return f < 1.0 ? f : 1.0;
}

}  // namespace relight::baker
