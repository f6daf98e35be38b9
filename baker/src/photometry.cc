// Float64 Legendre/SH photometry: the reference the fixed-point runtime
// (runtime/engine/src/sh_eval.cc, legendre_weights.cc) is tested against.
//
// Real SH are evaluated in Cartesian form (sh_index.h conventions):
//   Y_lm = q_l^m(z) * C_m(x, y),  Y_l-m = q_l^m(z) * S_m(x, y),
//   C_m + i S_m = (x + i y)^m = sin^m(theta) e^{i m phi},
// with q_l^m = sqrt(2) K_lm P_l^m(z) / sin^m(theta) (no sqrt(2) for m = 0), a
// polynomial in z obtained by the normalised recurrences below. No trig, no
// pole singularity, and the same algorithm the runtime runs in fixed point.
#include "relight/baker/photometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Walks the normalised recurrence for one direction and hands every term to
// emit(t, value).
template <typename Emit>
void ForEachSh(int degree, const Vec3& dir, Emit emit) {
  if (degree < 0) throw std::invalid_argument("SH degree must be >= 0");
  const double x = dir[0], y = dir[1], z = dir[2];
  double q_mm = std::sqrt(1.0 / (4.0 * kPi));  // q_0^0 = K_00
  double c = 1.0, s = 0.0;                     // C_m, S_m
  for (int m = 0; m <= degree; ++m) {
    if (m > 0) {
      // Seed: q_m^m = -sqrt((2m+1)/(2m)) q_{m-1}^{m-1}, and sqrt(2) once at m = 1.
      q_mm *= -std::sqrt((2.0 * m + 1.0) / (2.0 * m));
      if (m == 1) q_mm *= std::sqrt(2.0);
      const double c_next = x * c - y * s;
      s = x * s + y * c;
      c = c_next;
    }
    double q_prev = 0.0, q = q_mm;  // q_{l-1}^m (0 below l = m), q_l^m
    for (int l = m; l <= degree; ++l) {
      if (l > m) {
        // q_l^m = a (z q_{l-1}^m - b q_{l-2}^m), a = sqrt((4l^2-1)/(l^2-m^2)),
        // b = sqrt(((l-1)^2-m^2)/(4(l-1)^2-1)).
        const double a = std::sqrt((4.0 * l * l - 1.0) / (double(l) * l - double(m) * m));
        const double b =
            std::sqrt((double(l - 1) * (l - 1) - double(m) * m) / (4.0 * (l - 1) * (l - 1) - 1.0));
        const double q_next = a * (z * q - b * q_prev);
        q_prev = q;
        q = q_next;
      }
      if (m == 0) {
        emit(ShIndex(l, 0), q);
      } else {
        emit(ShIndex(l, m), q * c);
        emit(ShIndex(l, -m), q * s);
      }
    }
  }
}

}  // namespace

double LegendreP(int l, double x) {
  if (l < 0) throw std::invalid_argument("Legendre degree must be >= 0");
  if (l == 0) return 1.0;
  double p_prev = 1.0, p = x;
  for (int n = 1; n < l; ++n) {
    // Bonnet: (n+1) P_{n+1} = (2n+1) x P_n - n P_{n-1}
    const double p_next = ((2.0 * n + 1.0) * x * p - n * p_prev) / (n + 1.0);
    p_prev = p;
    p = p_next;
  }
  return p;
}

double AssocLegendreP(int l, int m, double x) {
  if (m < 0 || m > l) throw std::invalid_argument("AssocLegendreP needs 0 <= m <= l");
  // P_m^m = (-1)^m (2m-1)!! (1-x^2)^{m/2}  (Condon-Shortley phase)
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - x * x));
  double p_mm = 1.0;
  for (int i = 1; i <= m; ++i) p_mm *= -(2.0 * i - 1.0) * sin_theta;
  if (l == m) return p_mm;
  double p_prev = p_mm, p = x * (2.0 * m + 1.0) * p_mm;
  for (int n = m + 1; n < l; ++n) {
    // (n-m+1) P_{n+1}^m = (2n+1) x P_n^m - (n+m) P_{n-1}^m
    const double p_next = ((2.0 * n + 1.0) * x * p - (n + m) * p_prev) / (n - m + 1.0);
    p_prev = p;
    p = p_next;
  }
  return p;
}

double ShY(int l, int m, const Vec3& dir) {
  if (l < 0 || m < -l || m > l) throw std::invalid_argument("ShY needs -l <= m <= l");
  const int wanted = ShIndex(l, m);
  double value = 0.0;
  ForEachSh(l, dir, [&](int t, double v) {
    if (t == wanted) value = v;
  });
  return value;
}

void EvalShBasis(int degree, const Vec3& dir, double* out) {
  ForEachSh(degree, dir, [out](int t, double v) { out[t] = v; });
}

double SigmaFactor(int degree, int l) {
  if (l == 0) return 1.0;
  // Dobashi Eq. 13
  const double x = kPi * l / (degree + 1.0);
  return std::sin(x) / x;
}

std::vector<double> LegendreWeights(const std::vector<double>& samples_cd, int degree) {
  if (samples_cd.size() < 3) throw std::invalid_argument("LegendreWeights needs M >= 2");
  if (degree < 0) throw std::invalid_argument("Legendre degree must be >= 0");
  const int M = static_cast<int>(samples_cd.size()) - 1;
  const double d_gamma = kPi / M;
  std::vector<double> w(degree + 1, 0.0);
  for (int k = 0; k <= M; ++k) {
    const double gamma = k * d_gamma;
    const double t_k = (k == 0 || k == M) ? 0.5 : 1.0;  // trapezoid end weights
    const double c = std::cos(gamma), s = std::sin(gamma);
    for (int l = 0; l <= degree; ++l) w[l] += t_k * samples_cd[k] * LegendreP(l, c) * s;
  }
  // Dobashi Eq. 19: w_l = (2l+1)/2 { ... } dgamma
  for (int l = 0; l <= degree; ++l) w[l] *= (2.0 * l + 1.0) / 2.0 * d_gamma;
  return w;
}

void UpdateLegendreWeights(std::vector<double>* weights, int M, int k, double old_cd,
                           double new_cd) {
  if (M < 2 || k < 0 || k > M) throw std::invalid_argument("UpdateLegendreWeights: bad M or k");
  const double d_gamma = kPi / M;
  const double gamma = k * d_gamma;
  const double t_k = (k == 0 || k == M) ? 0.5 : 1.0;
  const double c = std::cos(gamma), s = std::sin(gamma);
  // Dobashi Eq. 21, with the (2l+1)/2 of Eq. 19 the paper leaves implicit.
  for (size_t l = 0; l < weights->size(); ++l) {
    const int li = static_cast<int>(l);
    (*weights)[l] +=
        t_k * (new_cd - old_cd) * LegendreP(li, c) * s * d_gamma * (2.0 * li + 1.0) / 2.0;
  }
}

std::vector<double> SampleLid(const Lid& lid, int M) {
  if (M < 2) throw std::invalid_argument("SampleLid needs M >= 2");
  std::vector<double> samples(M + 1);
  for (int k = 0; k <= M; ++k) samples[k] = lid.Evaluate(180.0 * k / M);
  return samples;
}

void AimCoefficients(int degree, const Vec3& aim, double* out) {
  // Dobashi Eq. 10
  ForEachSh(degree, aim, [out](int t, double v) {
    const int l = ShDegreeOf(t);
    out[t] = 4.0 * kPi / (2.0 * l + 1.0) * v;
  });
}

std::vector<double> TermWeights(const std::vector<double>& legendre_weights, const Vec3& aim,
                                bool use_sigma) {
  if (legendre_weights.empty()) throw std::invalid_argument("TermWeights needs w_0");
  const int degree = static_cast<int>(legendre_weights.size()) - 1;
  std::vector<double> out(ShTermCount(degree));
  AimCoefficients(degree, aim, out.data());
  // Dobashi Eq. 18: sigma(N,l) w_l A_lm
  for (int t = 0; t < ShTermCount(degree); ++t) {
    const int l = ShDegreeOf(t);
    out[t] *= legendre_weights[l] * (use_sigma ? SigmaFactor(degree, l) : 1.0);
  }
  return out;
}

double ShIntensity(int degree, const std::vector<double>& term_weights, const Vec3& dir) {
  if (term_weights.size() < static_cast<size_t>(ShTermCount(degree))) {
    throw std::invalid_argument("ShIntensity: fewer weights than terms");
  }
  double sum = 0.0;
  ForEachSh(degree, dir, [&](int t, double v) { sum += term_weights[t] * v; });
  return sum;
}

}  // namespace relight::baker
