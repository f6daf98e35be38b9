#include "relight/baker/polar_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "relight/baker/photometry.h"
#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string Num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}

// A "nice" ring spacing: 1, 2 or 5 x 10^k so that about 4 rings fit.
double RingStep(double max_cd) {
  const double raw = max_cd / 4;
  const double p = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    if (m * p >= raw) return m * p;
  }
  return 10 * p;
}

const char* Colour(size_t i) {
  static const char* kColours[] = {"#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e"};
  return kColours[i % 5];
}

// Points of one half-plane curve: C on the right half, C + 180 on the left.
template <typename Intensity>
std::string Path(double c_right, double cx, double cy, double scale, Intensity intensity) {
  std::string d;
  for (int side = 0; side < 2; ++side) {
    const double c = side == 0 ? c_right : c_right + 180;
    for (int k = 0; k <= 180; ++k) {
      const double g = side == 0 ? k : 180 - k;
      const double r = std::max(0.0, intensity(c, g)) * scale;
      const double gr = g * kPi / 180;
      const double x = cx + (side == 0 ? 1 : -1) * r * std::sin(gr), y = cy + r * std::cos(gr);
      d += (d.empty() ? "M" : "L") + Num(x) + "," + Num(y) + " ";
    }
  }
  return d;
}

}  // namespace

std::string LidPolarSvg(const Lid& lid, const PolarPlotOptions& o) {
  const LidErrorModel model(lid);
  const int n = std::clamp(o.degree, 0, kMaxShDegree);
  const std::vector<double>& coef = model.coefficients();
  std::vector<double> y(ShTermCount(n));
  const auto series = [&](ShWindow w, double c, double g) {
    const double cr = c * kPi / 180, gr = g * kPi / 180;
    EvalShBasis(n, Vec3{std::sin(gr) * std::cos(cr), std::sin(gr) * std::sin(cr), -std::cos(gr)},
                y.data());
    double v = 0;
    for (int t = 0; t < ShTermCount(n); ++t) v += ShWindowFactor(w, n, ShDegreeOf(t)) * coef[t] * y[t];
    return v;
  };
  const auto exact = [&](double c, double g) { return lid.Evaluate(c, g); };
  double peak = 0;
  for (double c : {0.0, 90.0, 180.0, 270.0}) {
    for (int k = 0; k <= 360; ++k) peak = std::max(peak, exact(c, k * 0.5));
  }
  for (ShWindow w : o.windows) {
    for (double c : {0.0, 90.0, 180.0, 270.0}) {
      for (int k = 0; k <= 90; ++k) peak = std::max(peak, series(w, c, k * 2.0));
    }
  }
  const double size = o.size_px, legend_h = 22.0 * (3 + static_cast<double>(o.windows.size()));
  const double cx = size / 2, cy = size / 2, radius = size / 2 - 40;
  const double step = RingStep(peak > 0 ? peak : 1), top = std::ceil(peak / step) * step;
  const double scale = radius / (top > 0 ? top : 1);
  std::string s = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Num(size) + "\" height=\"" +
                  Num(size + legend_h) + "\" font-family=\"sans-serif\" font-size=\"12\">\n";
  s += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s += "<text x=\"10\" y=\"18\" font-size=\"14\">" + o.title + "</text>\n";
  for (double r = step; r <= top + 1e-9; r += step) {
    s += "<circle cx=\"" + Num(cx) + "\" cy=\"" + Num(cy) + "\" r=\"" + Num(r * scale) +
         "\" fill=\"none\" stroke=\"#ccc\"/>\n";
    char label[32];
    std::snprintf(label, sizeof label, "%g cd", r);
    s += "<text x=\"" + Num(cx + 3) + "\" y=\"" + Num(cy + r * scale - 3) + "\" fill=\"#888\">" +
         label + "</text>\n";
  }
  for (int a = 0; a < 360; a += 30) {
    const double ar = a * kPi / 180;
    s += "<line x1=\"" + Num(cx) + "\" y1=\"" + Num(cy) + "\" x2=\"" + Num(cx + radius * std::sin(ar)) +
         "\" y2=\"" + Num(cy + radius * std::cos(ar)) + "\" stroke=\"#e4e4e4\"/>\n";
    const int label = a <= 180 ? a : 360 - a;
    s += "<text x=\"" + Num(cx + (radius + 16) * std::sin(ar) - 8) + "\" y=\"" +
         Num(cy + (radius + 16) * std::cos(ar) + 4) + "\" fill=\"#888\">" + std::to_string(label) +
         "°</text>\n";
  }
  const auto curve = [&](const std::string& d, const char* colour, bool dashed, double width) {
    s += "<path d=\"" + d + "\" fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"" + Num(width) +
         "\"" + (dashed ? " stroke-dasharray=\"6,4\"" : "") + "/>\n";
  };
  for (size_t i = 0; i < o.windows.size(); ++i) {
    const ShWindow w = o.windows[i];
    const auto f = [&](double c, double g) { return series(w, c, g); };
    curve(Path(0, cx, cy, scale, f), Colour(i), false, 1.5);
    curve(Path(90, cx, cy, scale, f), Colour(i), true, 1.5);
  }
  curve(Path(0, cx, cy, scale, exact), "black", false, 2.0);
  curve(Path(90, cx, cy, scale, exact), "black", true, 2.0);
  double ly = size + 8;
  const auto legend = [&](const char* colour, const std::string& text) {
    s += "<line x1=\"12\" y1=\"" + Num(ly) + "\" x2=\"42\" y2=\"" + Num(ly) + "\" stroke=\"" + colour +
         "\" stroke-width=\"2\"/><text x=\"50\" y=\"" + Num(ly + 4) + "\">" + text + "</text>\n";
    ly += 22;
  };
  legend("black", "the file (C0-C180 solid, C90-C270 dashed; right half C0 / C90)");
  for (size_t i = 0; i < o.windows.size(); ++i) {
    const ShWindow w = o.windows[i];
    char text[256];
    std::snprintf(text, sizeof text,
                  "SH degree %d, window %s: zonal flux error %.2f%%, L2 error %.2f%%, lowest %.2f%% of peak",
                  n, ShWindowName(w), 100 * model.Error(n, w, LidErrorMeasure::kZonalFlux),
                  100 * model.Error(n, w, LidErrorMeasure::kL2), 100 * model.MinimumRelative(n, w));
    legend(Colour(i), text);
  }
  s += "</svg>\n";
  return s;
}

}  // namespace relight::baker
