// PhotometricTable: symmetry folding, bilinear evaluation in the file's own
// angles, expansion to the full circle, flux; LoadPhotometricFile.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <memory>
#include <sstream>

#include "bounded_read.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/scene.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kAngleEps = 1e-9;  // degrees: angles closer than this are one angle

double Wrap360(double a) {
  double w = std::fmod(a, 360.0);
  if (w < 0) w += 360.0;
  if (w >= 360.0) w -= 360.0;
  return w;
}

// Linear in gamma along one plane (`row` has one value per gamma), 0 outside.
double AlongGamma(const std::vector<double>& gamma, const double* row, double g) {
  if (gamma.empty()) return 0;
  if (g < gamma.front() - kAngleEps || g > gamma.back() + kAngleEps) return 0;
  if (gamma.size() == 1) return row[0];
  const size_t hi = static_cast<size_t>(std::upper_bound(gamma.begin(), gamma.end(), g) -
                                        gamma.begin());
  if (hi == 0) return row[0];
  if (hi >= gamma.size()) return row[gamma.size() - 1];
  const double t = (g - gamma[hi - 1]) / (gamma[hi] - gamma[hi - 1]);
  return row[hi - 1] + t * (row[hi] - row[hi - 1]);
}

// Bilinear in (C, gamma) over planes c[0..n) where C in [c.front(), c.back()]
// (clamped), plus, when wrap, from the last plane round to c[0] + 360.
double Bilinear(const std::vector<double>& c, const std::vector<double>& gamma,
                const std::vector<double>& candela, double cc, double g, bool wrap) {
  const size_t n = c.size(), m = gamma.size();
  const auto row = [&](size_t p) { return candela.data() + p * m; };
  if (n == 1) return AlongGamma(gamma, row(0), g);
  size_t lo = 0, hi = 0;
  double t = 0;
  if (wrap && cc > c.back()) {
    lo = n - 1;
    hi = 0;
    t = (cc - c.back()) / (c.front() + 360.0 - c.back());
  } else if (cc <= c.front()) {
    lo = hi = 0;
  } else if (cc >= c.back()) {
    lo = hi = n - 1;
  } else {
    hi = static_cast<size_t>(std::upper_bound(c.begin(), c.end(), cc) - c.begin());
    lo = hi - 1;
    t = (cc - c[lo]) / (c[hi] - c[lo]);
  }
  const double a = AlongGamma(gamma, row(lo), g);
  if (t == 0 || lo == hi) return a;
  return a + t * (AlongGamma(gamma, row(hi), g) - a);
}

// Direction folding shared by both tables: gamma into [0, 180] (a gamma past
// 180 is the opposite C plane), C into [0, 360).
void FoldDirection(double* c, double* g) {
  double gg = std::fmod(std::fabs(*g), 360.0);
  double cc = *c;
  if (gg > 180.0) {
    gg = 360.0 - gg;
    cc += 180.0;
  }
  *g = gg;
  *c = Wrap360(cc);
}

// The symmetry's images of a plane angle, in [0, 360).
std::vector<double> Images(CSymmetry s, double c) {
  switch (s) {
    case CSymmetry::kAxial:
    case CSymmetry::kNone:
      return {Wrap360(c)};
    case CSymmetry::kQuadrant:
      return {Wrap360(c), Wrap360(180 - c), Wrap360(180 + c), Wrap360(360 - c)};
    case CSymmetry::kBilateral:
      return {Wrap360(c), Wrap360(360 - c)};
    case CSymmetry::kBilateral90:
      return {Wrap360(c), Wrap360(180 - c)};
  }
  return {Wrap360(c)};
}

// Integral of I(gamma) sin(gamma) dgamma for I linear between the samples,
// exactly: on [a, b], I = p + q gamma and the primitive of
// (p + q x) sin x is -(p + q x) cos x + q sin x.
double PlaneIntegral(const std::vector<double>& gamma_deg, const double* row) {
  double sum = 0;
  for (size_t k = 0; k + 1 < gamma_deg.size(); ++k) {
    const double a = gamma_deg[k] * kPi / 180, b = gamma_deg[k + 1] * kPi / 180;
    const double q = (row[k + 1] - row[k]) / (b - a);
    const double p = row[k] - q * a;
    const auto primitive = [&](double x) { return -(p + q * x) * std::cos(x) + q * std::sin(x); };
    sum += primitive(b) - primitive(a);
  }
  return sum;
}

}  // namespace

const char* CSymmetryName(CSymmetry symmetry) {
  switch (symmetry) {
    case CSymmetry::kAxial: return "axial (one C plane)";
    case CSymmetry::kQuadrant: return "quadrant (C 0-90)";
    case CSymmetry::kBilateral: return "bilateral (C 0-180)";
    case CSymmetry::kBilateral90: return "bilateral (C 90-270)";
    case CSymmetry::kNone: return "none (C 0-360)";
  }
  return "?";
}

double PhotometricTable::Evaluate(double c_in, double g_in) const {
  double c = c_in, g = g_in;
  FoldDirection(&c, &g);
  switch (symmetry) {
    case CSymmetry::kAxial:
      c = c_deg.empty() ? 0 : c_deg.front();
      break;
    case CSymmetry::kQuadrant:
      if (c > 180) c = 360 - c;
      if (c > 90) c = 180 - c;
      break;
    case CSymmetry::kBilateral:
      if (c > 180) c = 360 - c;
      break;
    case CSymmetry::kBilateral90:
      if (c < 90) c = 180 - c;
      if (c > 270) c = 540 - c;
      break;
    case CSymmetry::kNone:
      break;
  }
  return Bilinear(c_deg, gamma_deg, candela, c, g, symmetry == CSymmetry::kNone);
}

double PhotometricTable::PeakCandela() const {
  return candela.empty() ? 0 : *std::max_element(candela.begin(), candela.end());
}

double PhotometricTable::LuminousFlux() const {
  const FullCircleTable full = ExpandToFullCircle(*this);
  const size_t m = full.gamma_deg.size();
  double flux = 0;
  for (size_t p = 0; p + 1 < full.c_deg.size(); ++p) {
    const double dc = (full.c_deg[p + 1] - full.c_deg[p]) * kPi / 180;
    // Linear in C between planes: the trapezoid rule is exact.
    flux += 0.5 * dc *
            (PlaneIntegral(full.gamma_deg, full.candela.data() + p * m) +
             PlaneIntegral(full.gamma_deg, full.candela.data() + (p + 1) * m));
  }
  return flux;
}

double FullCircleTable::Evaluate(double c_in, double g_in) const {
  double c = c_in, g = g_in;
  FoldDirection(&c, &g);
  return Bilinear(c_deg, gamma_deg, candela, c, g, /*wrap=*/false);
}

FullCircleTable ExpandToFullCircle(const PhotometricTable& table) {
  FullCircleTable out;
  out.gamma_deg = table.gamma_deg;
  std::vector<double> angles = {0.0};
  if (table.symmetry != CSymmetry::kAxial) {
    for (double c : table.c_deg) {
      for (double a : Images(table.symmetry, c)) angles.push_back(a);
    }
  }
  std::sort(angles.begin(), angles.end());
  for (double a : angles) {
    if (out.c_deg.empty() || a > out.c_deg.back() + kAngleEps) out.c_deg.push_back(a);
  }
  out.c_deg.push_back(360.0);
  const size_t m = table.gamma_deg.size();
  out.candela.resize(out.c_deg.size() * m);
  for (size_t p = 0; p < out.c_deg.size(); ++p) {
    // The plane at 360 is the plane at 0 (and evaluating at 360 folds to 0).
    const double c = p + 1 == out.c_deg.size() ? 0.0 : out.c_deg[p];
    for (size_t g = 0; g < m; ++g) out.candela[p * m + g] = table.Evaluate(c, table.gamma_deg[g]);
  }
  return out;
}

Lid MakeLid(PhotometricTable table) {
  Lid lid;
  lid.file_path = table.path;
  lid.peak_cd = table.PeakCandela();
  if (table.symmetry == CSymmetry::kAxial) {
    lid.kind = LidKind::kTable;
    lid.gamma_deg = table.gamma_deg;
    lid.candela = table.candela;
  } else {
    lid.kind = LidKind::kCGamma;
    lid.file = std::make_shared<const PhotometricTable>(std::move(table));
  }
  return lid;
}

Lid LoadLid(const std::string& path) { return MakeLid(LoadPhotometricFile(path)); }

PhotometricTable LoadPhotometricFile(const std::string& path) {
  std::string text, why;
  if (!ReadBoundedFile(path, kMaxPhotometricFileBytes, &text, &why)) {
    throw SceneError(path, 0, "cannot read the photometric file: " + why);
  }
  std::string ext;
  const size_t dot = path.find_last_of('.');
  if (dot != std::string::npos && path.find('/', dot) == std::string::npos) {
    ext = path.substr(dot + 1);
    for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  }
  if (ext == "ies") return ParseIes(text, path);
  if (ext == "ldt") return ParseEulumdat(text, path);
  throw SceneError(path, 0,
                   "unknown photometric file type '." + ext + "' (expected .ies or .ldt)");
}

}  // namespace relight::baker
