// False-colour lux plans (see lux_map_svg.h).
#include "lux_map_svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace relight::cli {
namespace {

constexpr double kPanelWidth = 640;  // drawing area of one grid, px
constexpr double kPanelHeight = 420;
constexpr double kMargin = 60;
constexpr double kBarWidth = 18;
constexpr double kMinLabelCell = 30;  // cells narrower than this get no value

std::string Fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

// Lux with as many decimals as the magnitude needs.
std::string LuxText(double lux) {
  if (lux == 0) return "0";
  if (lux >= 100) return Fmt("%.0f", lux);
  if (lux >= 10) return Fmt("%.1f", lux);
  return Fmt("%.2f", lux);
}

// Black or white, whichever reads better on a "#rrggbb" fill.
const char* TextColourOn(const std::string& fill) {
  const int rgb = static_cast<int>(std::strtol(fill.c_str() + 1, nullptr, 16));
  const double luma = 0.2126 * ((rgb >> 16) & 255) + 0.7152 * ((rgb >> 8) & 255) + 0.0722 * (rgb & 255);
  return luma < 110 ? "white" : "black";
}

double Distance(const std::vector<double>& p, size_t a, size_t b) {
  const double dx = p[3 * a] - p[3 * b], dy = p[3 * a + 1] - p[3 * b + 1], dz = p[3 * a + 2] - p[3 * b + 2];
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// The colour bar beside a panel at (x, y), `height` px tall, 0..top lux.
std::string ColourBar(double x, double y, double height, double top) {
  std::string s;
  const int bands = 50;
  for (int i = 0; i < bands; ++i) {
    const double v = top * (i + 0.5) / bands;
    const double y0 = y + height * (1 - static_cast<double>(i + 1) / bands);
    s += "<rect x=\"" + Fmt("%.1f", x) + "\" y=\"" + Fmt("%.2f", y0) + "\" width=\"" + Fmt("%.0f", kBarWidth) +
         "\" height=\"" + Fmt("%.2f", height / bands + 0.3) + "\" fill=\"" + LuxColour(v, top) + "\"/>\n";
  }
  for (int t = 0; t <= 5; ++t) {
    const double v = top * t / 5, ty = y + height * (1 - t / 5.0);
    s += "<text x=\"" + Fmt("%.1f", x + kBarWidth + 4) + "\" y=\"" + Fmt("%.1f", ty + 4) +
         "\" font-size=\"11\">" + LuxText(v) + "</text>\n";
  }
  s += "<text x=\"" + Fmt("%.1f", x) + "\" y=\"" + Fmt("%.1f", y - 8) + "\" font-size=\"11\">lux</text>\n";
  return s;
}

std::string Panel(const GridLux& g, double top_y) {
  const LuxSummary sum = Summarise(g.lux);
  const double top = ScaleTop(sum.max);
  std::string s = "<text x=\"" + Fmt("%.0f", kMargin) + "\" y=\"" + Fmt("%.0f", top_y + 18) +
                  "\" font-size=\"15\" font-weight=\"bold\">grid '" + Escape(g.name) + "': illuminance E (lux)</text>\n";
  s += "<text x=\"" + Fmt("%.0f", kMargin) + "\" y=\"" + Fmt("%.0f", top_y + 36) + "\" font-size=\"12\">" +
       std::to_string(g.lux.size()) + " points  ·  Emin " + LuxText(sum.min) + " lx  ·  Eavg " + LuxText(sum.avg) +
       " lx  ·  Emax " + LuxText(sum.max) + " lx  ·  U0 = Emin/Eavg " + Fmt("%.3f", sum.u0) + "</text>\n";
  const double y0 = top_y + 50;
  if (g.columns > 0 && g.rows > 0 && static_cast<size_t>(g.columns) * g.rows == g.lux.size()) {
    // Cells in the grid's own (column, row) frame, sized by the point spacing; row 0 at the bottom.
    const double du = g.columns > 1 ? Distance(g.xyz_m, 0, 1) : 1.0;
    const double dv = g.rows > 1 ? Distance(g.xyz_m, 0, g.columns) : du;
    const double width_m = du * g.columns, height_m = dv * g.rows;
    const double scale = std::min(kPanelWidth / width_m, kPanelHeight / height_m);
    const double cw = du * scale, ch = dv * scale;
    const bool labels = cw >= kMinLabelCell && ch >= 14;
    for (unsigned r = 0; r < g.rows; ++r) {
      for (unsigned c = 0; c < g.columns; ++c) {
        const double e = g.lux[static_cast<size_t>(r) * g.columns + c];
        const double x = kMargin + c * cw, y = y0 + (g.rows - 1 - r) * ch;
        s += "<rect x=\"" + Fmt("%.2f", x) + "\" y=\"" + Fmt("%.2f", y) + "\" width=\"" + Fmt("%.2f", cw) +
             "\" height=\"" + Fmt("%.2f", ch) + "\" fill=\"" + LuxColour(e, top) + "\"><title>" + LuxText(e) +
             " lx</title></rect>\n";
        if (labels) {
          s += "<text x=\"" + Fmt("%.2f", x + cw / 2) + "\" y=\"" + Fmt("%.2f", y + ch / 2 + 4) +
               "\" font-size=\"10\" text-anchor=\"middle\" fill=\"" + TextColourOn(LuxColour(e, top)) + "\">" +
               LuxText(e) + "</text>\n";
        }
      }
    }
    const double bottom = y0 + height_m * scale;
    s += "<text x=\"" + Fmt("%.0f", kMargin) + "\" y=\"" + Fmt("%.1f", bottom + 16) + "\" font-size=\"11\">" +
         Fmt("%.2f", width_m) + " m × " + Fmt("%.2f", height_m) + " m, " + std::to_string(g.columns) + " × " +
         std::to_string(g.rows) + " points at " + Fmt("%.3f", du) + " m × " + Fmt("%.3f", dv) +
         " m (first point bottom left, columns to the right, rows upward)</text>\n";
    s += ColourBar(kMargin + width_m * scale + 20, y0, std::max(120.0, height_m * scale), top);
  } else {
    // A list of points: dots at their (x, y) seen from above.
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    for (size_t p = 0; p < g.lux.size(); ++p) {
      xmin = std::min(xmin, g.xyz_m[3 * p]), xmax = std::max(xmax, g.xyz_m[3 * p]);
      ymin = std::min(ymin, g.xyz_m[3 * p + 1]), ymax = std::max(ymax, g.xyz_m[3 * p + 1]);
    }
    const double span = std::max({xmax - xmin, ymax - ymin, 1e-3});
    const double scale = std::min(kPanelWidth, kPanelHeight) / span;
    for (size_t p = 0; p < g.lux.size(); ++p) {
      const double x = kMargin + 10 + (g.xyz_m[3 * p] - xmin) * scale;
      const double y = y0 + 10 + (ymax - g.xyz_m[3 * p + 1]) * scale;
      s += "<circle cx=\"" + Fmt("%.2f", x) + "\" cy=\"" + Fmt("%.2f", y) + "\" r=\"7\" fill=\"" +
           LuxColour(g.lux[p], top) + "\" stroke=\"#333\"><title>" + LuxText(g.lux[p]) + " lx</title></circle>\n";
      s += "<text x=\"" + Fmt("%.2f", x + 10) + "\" y=\"" + Fmt("%.2f", y + 4) + "\" font-size=\"10\">" +
           LuxText(g.lux[p]) + "</text>\n";
    }
    s += ColourBar(kMargin + span * scale + 80, y0, 200, top);
  }
  return s;
}

}  // namespace

LuxSummary Summarise(const std::vector<double>& lux) {
  LuxSummary s;
  if (lux.empty()) return s;
  s.min = *std::min_element(lux.begin(), lux.end());
  s.max = *std::max_element(lux.begin(), lux.end());
  double sum = 0;
  for (double e : lux) sum += e;
  s.avg = sum / static_cast<double>(lux.size());
  s.u0 = s.avg > 0 ? s.min / s.avg : 0;
  return s;
}

double ScaleTop(double max_lux) {
  static const double kSteps[] = {1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8};
  for (double decade = 1; decade < 1e12; decade *= 10) {
    for (double step : kSteps) {
      if (step * decade >= max_lux) return step * decade;
    }
  }
  return max_lux;
}

std::string LuxColour(double lux, double top) {
  // Stops of a blue-cyan-green-yellow-red ramp, evenly spaced in lux.
  static const double kStops[][3] = {{20, 30, 120}, {30, 120, 230}, {40, 200, 200},
                                     {80, 200, 60}, {240, 220, 40}, {220, 50, 30}};
  constexpr int kLast = 5;
  double t = top > 0 ? lux / top : 0;
  t = std::clamp(t, 0.0, 1.0) * kLast;
  const int i = std::min(static_cast<int>(t), kLast - 1);
  const double w = t - i;
  char buf[8];
  int rgb[3];
  for (int c = 0; c < 3; ++c) rgb[c] = static_cast<int>(std::lround(kStops[i][c] * (1 - w) + kStops[i + 1][c] * w));
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", rgb[0], rgb[1], rgb[2]);
  return buf;
}

std::string LuxMapSvg(const std::vector<GridLux>& grids, const std::string& subtitle) {
  const double panel = kPanelHeight + 110;
  const double height = 50 + panel * static_cast<double>(grids.size());
  std::string s = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  s += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + Fmt("%.0f", kPanelWidth + 2 * kMargin + 120) +
       "\" height=\"" + Fmt("%.0f", height) + "\" font-family=\"sans-serif\">\n";
  s += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  s += "<text x=\"" + Fmt("%.0f", kMargin) + "\" y=\"28\" font-size=\"13\">" + Escape(subtitle) + "</text>\n";
  for (size_t i = 0; i < grids.size(); ++i) s += Panel(grids[i], 40 + panel * static_cast<double>(i));
  s += "</svg>\n";
  return s;
}

}  // namespace relight::cli
