// The spherical-harmonic conventions shared by the float64 baker and the
// fixed-point runtime. Both sides must agree on every point here.
//
// * Directions: world frame is right-handed, z up, metres. A direction
//   (x, y, z) has polar angle theta from +z and azimuth phi from +x towards +y
//   (Dobashi Eq. 5-6).
// * Real SH are orthonormal over the sphere, with the Condon-Shortley phase
//   in the associated Legendre functions P_l^m (Dobashi Eq. 22 up to the
//   sqrt(2) that makes real harmonics orthonormal):
//     Y_l0  = K_l0 P_l^0(cos theta)
//     Y_lm  = sqrt(2) K_lm P_l^m(cos theta) cos(m phi),   m > 0
//     Y_l-m = sqrt(2) K_lm P_l^m(cos theta) sin(m phi),   m > 0
//     K_lm  = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!)
//   With this normalisation the addition theorem (Dobashi Eq. 7) holds:
//     P_l(a.b) = 4 pi/(2l+1) sum_m Y_lm(a) Y_lm(b).
// * Index order: term t = l*l + l + m, so l = 0..N, m = -l..l, and a degree-N
//   expansion has (N+1)^2 terms.
// * A "basis luminance" for term t is the scene lit by a point luminaire whose
//   intensity in direction r is Y_t(r) candela (Dobashi Eq. 15-17).
// * Run-time weight of term t = sigma(N,l) * w_l * A_lm(aim) (Dobashi Eq. 18),
//   A_lm = 4 pi/(2l+1) Y_lm(aim) (Eq. 10), w_l the Legendre weight of the
//   beam in candela (Eq. 3 / 19).
#pragma once

#include <cstddef>

#include <cstdint>

namespace relight {

// 529 terms; the bake rejects more. 22, not 16, for the narrowest zooms of
// real fixture types (11-12 degrees; docs/accuracy.md "Zoom at run time").
inline constexpr int kMaxShDegree = 22;

constexpr int ShTermCount(int degree) { return (degree + 1) * (degree + 1); }
constexpr int ShIndex(int l, int m) { return l * l + l + m; }
constexpr int ShDegreeOf(int t) {
  int l = 0;
  while ((l + 1) * (l + 1) <= t) ++l;
  return l;
}
constexpr int ShOrderOf(int t) {
  const int l = ShDegreeOf(t);
  return t - l * l - l;
}

// Offset of band l in concatenated band matrices: sum_{k<l} (2k+1)^2.
constexpr size_t ShRotationBandOffset(int l) {
  return static_cast<size_t>(l) * (2 * static_cast<size_t>(l) - 1) *
         (2 * static_cast<size_t>(l) + 1) / 3;
}

}  // namespace relight
