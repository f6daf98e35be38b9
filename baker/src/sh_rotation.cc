// Real-SH rotation (Ivanic & Ruedenberg) and the SH projection of a LID.
#include "relight/baker/sh_rotation.h"

#include <cmath>
#include <stdexcept>

#include "relight/baker/photometry.h"
#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Band l's matrix inside the concatenated storage, indexed by m, n in [-l, l].
struct Band {
  double* data;
  int l;
  double& operator()(int m, int n) const { return data[(m + l) * (2 * l + 1) + (n + l)]; }
};

// Ivanic & Ruedenberg's P: the step from band l-1 by one more rotation of band 1.
double P(int i, int l, int a, int b, const Band& r1, const Band& prev) {
  if (b == l) return r1(i, 1) * prev(a, l - 1) - r1(i, -1) * prev(a, -l + 1);
  if (b == -l) return r1(i, 1) * prev(a, -l + 1) + r1(i, -1) * prev(a, l - 1);
  return r1(i, 0) * prev(a, b);
}

}  // namespace

std::vector<double> ShRotationMatrices(int degree, const double r[3][3]) {
  if (degree < 0 || degree > kMaxShDegree) throw std::invalid_argument("SH rotation: bad degree");
  std::vector<double> out(ShRotationBandOffset(degree + 1), 0.0);
  out[0] = 1.0;
  if (degree == 0) return out;
  // Band 1 in real-SH order (m = -1, 0, 1 <-> y, z, x).
  const int axis_of[3] = {1, 2, 0};
  const Band r1{out.data() + ShRotationBandOffset(1), 1};
  for (int m = -1; m <= 1; ++m) {
    for (int n = -1; n <= 1; ++n) r1(m, n) = r[axis_of[m + 1]][axis_of[n + 1]];
  }
  for (int l = 2; l <= degree; ++l) {
    const Band prev{out.data() + ShRotationBandOffset(l - 1), l - 1};
    const Band cur{out.data() + ShRotationBandOffset(l), l};
    for (int m = -l; m <= l; ++m) {
      const int am = m < 0 ? -m : m;
      for (int n = -l; n <= l; ++n) {
        const double denom = (n == l || n == -l) ? 2.0 * l * (2.0 * l - 1.0)
                                                 : static_cast<double>(l + n) * (l - n);
        const double u = std::sqrt(static_cast<double>(l + m) * (l - m) / denom);
        const double d0 = m == 0 ? 1.0 : 0.0;
        const double v = 0.5 * std::sqrt((1.0 + d0) * (l + am - 1.0) * (l + am) / denom) * (1.0 - 2.0 * d0);
        const double w = -0.5 * std::sqrt((l - am - 1.0) * (l - am) / denom) * (1.0 - d0);
        double value = 0;
        if (u != 0) value += u * P(0, l, m, n, r1, prev);
        if (v != 0) {
          double vv;
          if (m == 0) {
            vv = P(1, l, 1, n, r1, prev) + P(-1, l, -1, n, r1, prev);
          } else if (m > 0) {
            vv = P(1, l, m - 1, n, r1, prev) * (m == 1 ? std::sqrt(2.0) : 1.0) -
                 (m == 1 ? 0.0 : P(-1, l, -m + 1, n, r1, prev));
          } else {
            vv = (m == -1 ? 0.0 : P(1, l, m + 1, n, r1, prev)) +
                 P(-1, l, -m - 1, n, r1, prev) * (m == -1 ? std::sqrt(2.0) : 1.0);
          }
          value += v * vv;
        }
        if (w != 0) {
          const double ww = m > 0 ? P(1, l, m + 1, n, r1, prev) + P(-1, l, -m - 1, n, r1, prev)
                                  : P(1, l, m - 1, n, r1, prev) - P(-1, l, -m + 1, n, r1, prev);
          value += w * ww;
        }
        cur(m, n) = value;
      }
    }
  }
  // The recurrence is for harmonics without the Condon-Shortley phase;
  // relight's carry (-1)^m (sh_index.h): conjugate each band by those signs.
  for (int l = 1; l <= degree; ++l) {
    const Band d{out.data() + ShRotationBandOffset(l), l};
    for (int m = -l; m <= l; ++m) {
      for (int n = -l; n <= l; ++n) {
        if (((m < 0 ? -m : m) + (n < 0 ? -n : n)) % 2 != 0) d(m, n) = -d(m, n);
      }
    }
  }
  return out;
}

std::vector<double> RotateSh(int degree, const std::vector<double>& bands,
                             const std::vector<double>& coef) {
  std::vector<double> out(ShTermCount(degree), 0.0);
  for (int l = 0; l <= degree; ++l) {
    const Band d{const_cast<double*>(bands.data()) + ShRotationBandOffset(l), l};
    for (int m = -l; m <= l; ++m) {
      double sum = 0;
      for (int n = -l; n <= l; ++n) sum += d(m, n) * coef[ShIndex(l, n)];
      out[ShIndex(l, m)] = sum;
    }
  }
  return out;
}

std::vector<double> ProjectLidSh(const Lid& lid, int degree) {
  if (degree < 0 || degree > kMaxShDegree) throw std::invalid_argument("ProjectLidSh: bad degree");
  // Simpson's rule over gamma (the ends carry sin(gamma) = 0), midpoints over C.
  constexpr int kRings = 1440, kSteps = 720;
  const double dg = kPi / kRings, dc = 2 * kPi / kSteps;
  std::vector<double> out(ShTermCount(degree), 0.0);
  std::vector<double> ring(kSteps), y(ShTermCount(degree));
  std::vector<double> cos_mc((degree + 1) * kSteps), sin_mc((degree + 1) * kSteps);
  for (int m = 0; m <= degree; ++m) {
    for (int k = 0; k < kSteps; ++k) {
      cos_mc[m * kSteps + k] = std::cos(m * (k + 0.5) * dc);
      sin_mc[m * kSteps + k] = std::sin(m * (k + 0.5) * dc);
    }
  }
  for (int j = 1; j < kRings; ++j) {
    const double g = j * dg;
    const double g_deg = g * 180.0 / kPi;
    if (lid.axisymmetric()) {
      ring.assign(kSteps, lid.Evaluate(g_deg));
    } else {
      for (int k = 0; k < kSteps; ++k) ring[k] = lid.Evaluate((k + 0.5) * 360.0 / kSteps, g_deg);
    }
    // Y at C = 0 on this ring: q_l^m(z) sin^m(gamma) (photometry.cc's Cartesian form).
    EvalShBasis(degree, Vec3{std::sin(g), 0.0, -std::cos(g)}, y.data());
    const double w = std::sin(g) * dg * (j % 2 == 1 ? 4.0 : 2.0) / 3.0;
    for (int m = 0; m <= degree; ++m) {
      double a = 0, b = 0;
      for (int k = 0; k < kSteps; ++k) {
        a += ring[k] * cos_mc[m * kSteps + k];
        b += ring[k] * sin_mc[m * kSteps + k];
      }
      a *= dc;
      b *= dc;
      for (int l = m; l <= degree; ++l) {
        const double f = y[ShIndex(l, m)] * w;
        out[ShIndex(l, m)] += f * a;
        if (m > 0) out[ShIndex(l, -m)] += f * b;
      }
    }
  }
  return out;
}

}  // namespace relight::baker
