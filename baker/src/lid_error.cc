#include "relight/baker/lid_error.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "relight/baker/photometry.h"
#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;
// Sphere sampling: Simpson over gamma (rings 1 .. kRings-1; the poles carry
// sin(gamma) = 0), midpoints over C.
constexpr int kRings = 720, kSteps = 360;
constexpr double kCellDeg = 10.0;  // zonal flux cells

double Sinc(double x) { return x == 0 ? 1.0 : std::sin(x) / x; }

double RingWeight(int j) {
  const double dg = kPi / kRings;
  return std::sin(j * dg) * dg * (j % 2 == 1 ? 4.0 : 2.0) / 3.0 * (2 * kPi / kSteps);
}

}  // namespace

const char* ShWindowName(ShWindow window) {
  switch (window) {
    case ShWindow::kNone: return "none";
    case ShWindow::kSigma: return "sigma";
    case ShWindow::kHanning: return "hanning";
    case ShWindow::kLanczos: return "lanczos";
    case ShWindow::kSloan: return "sloan";
  }
  return "?";
}

ShWindow ParseShWindow(const std::string& name) {
  for (ShWindow w : {ShWindow::kNone, ShWindow::kSigma, ShWindow::kHanning, ShWindow::kLanczos,
                     ShWindow::kSloan}) {
    if (name == ShWindowName(w)) return w;
  }
  throw std::invalid_argument("unknown SH window '" + name +
                              "' (expected none, sigma, hanning, lanczos or sloan)");
}

double ShWindowFactor(ShWindow window, int degree, int l) {
  if (l == 0) return 1.0;
  const double x = kPi * l / (degree + 1.0);
  switch (window) {
    case ShWindow::kNone: return 1.0;
    case ShWindow::kSigma: return Sinc(x);
    case ShWindow::kHanning: return 0.5 * (1.0 + std::cos(x));
    case ShWindow::kLanczos: return Sinc(x) * Sinc(x);
    case ShWindow::kSloan: {
      const double n = static_cast<double>(degree) * (degree + 1.0);
      const double ll = static_cast<double>(l) * (l + 1.0);
      return 1.0 / (1.0 + (ll * ll) / (n * n));
    }
  }
  return 1.0;
}

const char* LidErrorMeasureName(LidErrorMeasure measure) {
  return measure == LidErrorMeasure::kL2 ? "L2" : "zonal flux";
}

LidErrorModel::LidErrorModel(const Lid& lid) {
  const int terms = ShTermCount(kMaxShDegree);
  samples_.assign(static_cast<size_t>(kRings) * kSteps, 0.0);
  ring_y_.assign(static_cast<size_t>(kRings) * terms, 0.0);
  coef_.assign(terms, 0.0);
  std::vector<double> cos_mc((kMaxShDegree + 1) * kSteps), sin_mc((kMaxShDegree + 1) * kSteps);
  for (int m = 0; m <= kMaxShDegree; ++m) {
    for (int k = 0; k < kSteps; ++k) {
      const double c = (k + 0.5) * 2 * kPi / kSteps;
      cos_mc[m * kSteps + k] = std::cos(m * c);
      sin_mc[m * kSteps + k] = std::sin(m * c);
    }
  }
  for (int j = 1; j < kRings; ++j) {
    const double g = j * kPi / kRings, g_deg = g * 180 / kPi;
    double* ring = samples_.data() + static_cast<size_t>(j) * kSteps;
    for (int k = 0; k < kSteps; ++k) {
      ring[k] = lid.axisymmetric() ? lid.Evaluate(g_deg)
                                   : lid.Evaluate((k + 0.5) * 360.0 / kSteps, g_deg);
      peak_ = std::max(peak_, ring[k]);
    }
    double* y = ring_y_.data() + static_cast<size_t>(j) * terms;
    EvalShBasis(kMaxShDegree, Vec3{std::sin(g), 0.0, -std::cos(g)}, y);
    const double w = RingWeight(j);
    for (int m = 0; m <= kMaxShDegree; ++m) {
      double a = 0, b = 0;
      for (int k = 0; k < kSteps; ++k) {
        a += ring[k] * cos_mc[m * kSteps + k];
        b += ring[k] * sin_mc[m * kSteps + k];
      }
      for (int l = m; l <= kMaxShDegree; ++l) {
        coef_[ShIndex(l, m)] += w * y[ShIndex(l, m)] * a;
        if (m > 0) coef_[ShIndex(l, -m)] += w * y[ShIndex(l, m)] * b;
      }
    }
  }
}

void LidErrorModel::Synthesise(int degree, ShWindow window, std::vector<double>* out) const {
  const int terms = ShTermCount(kMaxShDegree);
  out->assign(samples_.size(), 0.0);
  std::vector<double> a(degree + 1), b(degree + 1);
  for (int j = 1; j < kRings; ++j) {
    const double* y = ring_y_.data() + static_cast<size_t>(j) * terms;
    for (int m = 0; m <= degree; ++m) {
      a[m] = b[m] = 0;
      for (int l = m; l <= degree; ++l) {
        const double f = ShWindowFactor(window, degree, l) * y[ShIndex(l, m)];
        a[m] += f * coef_[ShIndex(l, m)];
        if (m > 0) b[m] += f * coef_[ShIndex(l, -m)];
      }
    }
    double* ring = out->data() + static_cast<size_t>(j) * kSteps;
    for (int k = 0; k < kSteps; ++k) {
      const double c = (k + 0.5) * 2 * kPi / kSteps;
      double v = a[0];
      for (int m = 1; m <= degree; ++m) v += a[m] * std::cos(m * c) + b[m] * std::sin(m * c);
      ring[k] = v;
    }
  }
}

double LidErrorModel::Error(int degree, ShWindow window, LidErrorMeasure measure) const {
  std::vector<double> series;
  Synthesise(degree, window, &series);
  if (measure == LidErrorMeasure::kL2) {
    double err = 0, norm = 0;
    for (int j = 1; j < kRings; ++j) {
      const double w = RingWeight(j);
      for (int k = 0; k < kSteps; ++k) {
        const size_t i = static_cast<size_t>(j) * kSteps + k;
        err += w * (series[i] - samples_[i]) * (series[i] - samples_[i]);
        norm += w * samples_[i] * samples_[i];
      }
    }
    return norm > 0 ? std::sqrt(err / norm) : 0.0;
  }
  const int cells_g = static_cast<int>(180 / kCellDeg), cells_c = static_cast<int>(360 / kCellDeg);
  std::vector<double> diff(static_cast<size_t>(cells_g) * cells_c, 0.0);
  double flux = 0;
  for (int j = 1; j < kRings; ++j) {
    const double w = RingWeight(j);
    const int cg = std::min(cells_g - 1, static_cast<int>(j * 180.0 / kRings / kCellDeg));
    for (int k = 0; k < kSteps; ++k) {
      const size_t i = static_cast<size_t>(j) * kSteps + k;
      const int cc = static_cast<int>((k + 0.5) * 360.0 / kSteps / kCellDeg);
      diff[static_cast<size_t>(cg) * cells_c + cc] += w * (series[i] - samples_[i]);
      flux += w * samples_[i];
    }
  }
  double misplaced = 0;
  for (double d : diff) misplaced += std::abs(d);
  return flux > 0 ? 0.5 * misplaced / flux : 0.0;
}

double LidErrorModel::MinimumRelative(int degree, ShWindow window) const {
  std::vector<double> series;
  Synthesise(degree, window, &series);
  double lowest = 0;
  for (size_t i = kSteps; i < series.size(); ++i) lowest = std::min(lowest, series[i]);
  return peak_ > 0 ? lowest / peak_ : 0.0;
}

DegreeChoice ChooseShDegree(const LidErrorModel& model, double target, ShWindow window,
                            LidErrorMeasure measure, int min_degree) {
  DegreeChoice out;
  for (int n = std::max(0, min_degree); n <= kMaxShDegree; ++n) {
    out.degree = n;
    out.error = model.Error(n, window, measure);
    if (out.error <= target) {
      out.met = true;
      return out;
    }
  }
  return out;
}

LuminaireDegree ChooseLuminaireDegree(Luminaire* lum, double target, DirectModeKind mode) {
  LuminaireDegree d;
  d.name = lum->name;
  d.old_degree = lum->sh_degree;
  d.window = lum->use_sigma.value_or(mode == DirectModeKind::kAllInSh) ? ShWindow::kSigma
                                                                      : ShWindow::kNone;
  d.measure = mode == DirectModeKind::kExact ? LidErrorMeasure::kZonalFlux : LidErrorMeasure::kL2;
  d.choice = ChooseShDegree(LidErrorModel(NarrowestLid(lum->lid)), target, d.window, d.measure);
  lum->sh_degree = d.choice.degree;
  lum->sh_degree_given = true;
  return d;
}

std::vector<LuminaireDegree> ApplyLidErrorTarget(Scene* scene, double target, DirectModeKind mode) {
  std::vector<LuminaireDegree> out;
  for (Luminaire& lum : scene->luminaires) out.push_back(ChooseLuminaireDegree(&lum, target, mode));
  return out;
}

}  // namespace relight::baker
