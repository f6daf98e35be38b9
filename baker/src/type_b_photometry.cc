// Type B to (C, gamma): see type_b_photometry.h for the angle conventions.
#include "type_b_photometry.h"

#include <algorithm>
#include <cmath>

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRad = kPi / 180.0;

// Index i and weight w with x between a[i] and a[i+1] (w toward a[i+1]);
// false when x lies outside [a.front(), a.back()].
bool Bracket(const std::vector<double>& a, double x, size_t* i, double* w) {
  if (x < a.front() || x > a.back()) return false;
  if (a.size() == 1) {
    *i = 0;
    *w = 0;
    return true;
  }
  const size_t hi = static_cast<size_t>(std::upper_bound(a.begin(), a.end(), x) - a.begin());
  *i = std::min(hi == 0 ? 0 : hi - 1, a.size() - 2);
  *w = (x - a[*i]) / (a[*i + 1] - a[*i]);
  return true;
}

double FinestStep(const std::vector<double>& a, double fallback) {
  double step = fallback;
  for (size_t i = 1; i < a.size(); ++i) step = std::min(step, a[i] - a[i - 1]);
  return step;
}

}  // namespace

double EvaluateTypeB(const TypeBTable& b, double h_deg, double v_deg) {
  const bool symmetric = b.h_deg.front() == 0 && b.h_deg.back() == 90;
  if (symmetric) h_deg = std::fabs(h_deg);
  size_t ih = 0, iv = 0;
  double wh = 0, wv = 0;
  if (!Bracket(b.h_deg, h_deg, &ih, &wh) || !Bracket(b.v_deg, v_deg, &iv, &wv)) return 0;
  const size_t nv = b.v_deg.size();
  const auto at = [&](size_t h, size_t v) { return b.candela[h * nv + v]; };
  const size_t ih1 = std::min(ih + 1, b.h_deg.size() - 1), iv1 = std::min(iv + 1, nv - 1);
  const double lo = at(ih, iv) * (1 - wv) + at(ih, iv1) * wv;
  const double hi = at(ih1, iv) * (1 - wv) + at(ih1, iv1) * wv;
  return lo * (1 - wh) + hi * wh;
}

double TypeBAtCGamma(const TypeBTable& b, double c_deg, double gamma_deg) {
  // d = cos g f + sin g (cos C u + sin C l); sin H = -d.l, V = atan2(d.u, d.f).
  const double sg = std::sin(gamma_deg * kRad), cg = std::cos(gamma_deg * kRad);
  const double f = cg, u = sg * std::cos(c_deg * kRad), l = sg * std::sin(c_deg * kRad);
  if (f < 0) return 0;  // behind the flood
  const double h = std::asin(std::clamp(-l, -1.0, 1.0)) / kRad;
  const double v = std::atan2(u, f) / kRad;
  return EvaluateTypeB(b, h, v);
}

void ConvertTypeBToC(const TypeBTable& b, PhotometricTable* out) {
  const double finest = std::min(FinestStep(b.h_deg, 90), FinestStep(b.v_deg, 90));
  // Half the file's step: the second interpolation adds a quarter of the
  // first's error (bilinear error grows with the step squared).
  const double gamma_step = std::clamp(finest / 2, 0.25, 1.0);
  const double c_step = std::clamp(finest / 2, 0.5, 2.5);
  const int gammas = static_cast<int>(std::ceil(90 / gamma_step - 1e-9));
  const int planes = static_cast<int>(std::ceil(360 / c_step - 1e-9));
  out->symmetry = CSymmetry::kNone;
  out->c_deg.clear();
  out->gamma_deg.clear();
  out->candela.clear();
  for (int c = 0; c < planes; ++c) out->c_deg.push_back(360.0 * c / planes);
  for (int g = 0; g <= gammas; ++g) out->gamma_deg.push_back(90.0 * g / gammas);
  out->candela.reserve(out->c_deg.size() * out->gamma_deg.size());
  for (double c : out->c_deg) {
    for (double g : out->gamma_deg) out->candela.push_back(TypeBAtCGamma(b, c, g));
  }
}

}  // namespace relight::baker
