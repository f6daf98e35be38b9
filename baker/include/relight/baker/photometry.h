// Float64 photometry and spherical-harmonic math for the baker and for the
// reference every accuracy figure is measured against. Conventions (angles,
// normalisation, index order) are those of runtime/base/include/relight/base/sh_index.h;
// the fixed-point runtime mirrors each function here (runtime/include/relight/
// sh_eval.h, legendre_weights.h) and tests hold the two together.
#pragma once

#include <vector>

#include "relight/baker/scene.h"

namespace relight::baker {

// Legendre polynomial P_l(x), Bonnet recurrence.
double LegendreP(int l, double x);
// Associated Legendre P_l^m(x), 0 <= m <= l, with the Condon-Shortley phase.
double AssocLegendreP(int l, int m, double x);
// Real orthonormal SH Y_lm of a unit direction (x, y, z), -l <= m <= l.
double ShY(int l, int m, const Vec3& dir);
// All (N+1)^2 terms of a unit direction, in ShIndex order.
void EvalShBasis(int degree, const Vec3& dir, double* out);

// Sigma factor sigma(N, l) (Dobashi Eq. 13).
double SigmaFactor(int degree, int l);

// Legendre weights w_0..w_N in candela (Dobashi Eq. 19) from M+1 samples of the
// distribution at gamma = k * pi / M, k = 0..M.
std::vector<double> LegendreWeights(const std::vector<double>& samples_cd, int degree);
// Incremental update when sample k moves from old_cd to new_cd (Dobashi Eq. 21).
void UpdateLegendreWeights(std::vector<double>* weights, int M, int k, double old_cd, double new_cd);
// Samples a Lid at M+1 uniform gamma steps over [0, 180] degrees.
std::vector<double> SampleLid(const Lid& lid, int M);

// Beam axis of a fixture (runtime/bake/include/relight/bake/bake.h gives the convention).
Vec3 BeamAxis(MountingKind mounting, double pan_deg, double tilt_deg);
// Pan and tilt (degrees) that aim a fixture at `target` from `position`.
void AimAt(MountingKind mounting, const Vec3& position, const Vec3& target, double* pan_deg,
           double* tilt_deg);

// A_lm(aim) = 4 pi / (2l+1) Y_lm(aim) for all terms (Dobashi Eq. 10).
void AimCoefficients(int degree, const Vec3& aim, double* out);
// Per-term run-time weights sigma(N,l) w_l A_lm(aim) (Dobashi Eq. 18);
// use_sigma = false leaves the series undamped.
std::vector<double> TermWeights(const std::vector<double>& legendre_weights, const Vec3& aim,
                                bool use_sigma);
// The SH approximation of the beam in direction `dir`: sum_t weight_t Y_t(dir).
double ShIntensity(int degree, const std::vector<double>& term_weights, const Vec3& dir);

}  // namespace relight::baker
