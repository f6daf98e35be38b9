// The project's own photometric fixtures: analytic beams sampled on each
// format's grids, one file per format and symmetry case, plus malformed
// variants. `relight-lid fixtures fixtures/photometry` writes them.
#include "relight/baker/analytic_photometry.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRad = kPi / 180.0;

double CosPow(double gamma_deg, double k) {
  const double c = std::cos(gamma_deg * kRad);
  return c > 0 ? std::pow(c, k) : 0.0;
}

// Smallest difference between two azimuths, degrees.
double AngleBetween(double a, double b) {
  double d = std::fmod(std::fabs(a - b), 360.0);
  return d > 180 ? 360 - d : d;
}

std::vector<double> Steps(double from, double to, double step) {
  std::vector<double> out;
  const int n = static_cast<int>(std::lround((to - from) / step));
  for (int i = 0; i <= n; ++i) out.push_back(from + step * i);
  return out;
}

PhotometricTable Sample(const std::string& kind, CSymmetry symmetry, std::vector<double> c,
                        std::vector<double> gamma, double lamp_lumens, double multiplier) {
  PhotometricTable t;
  t.symmetry = symmetry;
  t.c_deg = std::move(c);
  t.gamma_deg = std::move(gamma);
  t.lamp_lumens = lamp_lumens > 0 ? lamp_lumens : 0;
  t.multiplier = multiplier;
  t.luminaire = "relight analytic " + kind;
  for (double cc : t.c_deg) {
    for (double g : t.gamma_deg) {
      // Rounded to 0.01 cd so the text round-trips exactly (multiplier 1).
      const double v = AnalyticCandela(kind, cc, g);
      t.candela.push_back(std::round(v * 100.0) / 100.0);
    }
  }
  return t;
}

PhotometricFixture Ies(const std::string& name, const std::string& version, PhotometricTable t) {
  t.format = PhotometricFormat::kIes;
  t.version = version;
  t.tilt = t.tilt_data.angle_deg.empty() ? "NONE" : "INCLUDE";
  PhotometricFixture f{name, version, t, WriteIes(t, version)};
  return f;
}

PhotometricFixture Ldt(const std::string& name, PhotometricTable t) {
  t.format = PhotometricFormat::kEulumdat;
  t.version = "EULUMDAT";
  t.tilt = "NONE";
  PhotometricFixture f{name, "EULUMDAT", t, WriteEulumdat(t)};
  return f;
}

// Replaces the first occurrence of `from` after `after` in `text`.
std::string ReplaceAfter(std::string text, const std::string& after, const std::string& from,
                         const std::string& to) {
  const size_t a = text.find(after);
  const size_t at = text.find(from, a == std::string::npos ? 0 : a + after.size());
  if (at == std::string::npos) throw std::logic_error("fixture edit: '" + from + "' not found");
  return text.replace(at, from.size(), to);
}

int LineOf(const std::string& text, size_t offset) {
  int line = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) line += text[i] == '\n' ? 1 : 0;
  return line;
}

int CountLines(const std::string& text) {
  int n = 0;
  for (char c : text) n += c == '\n' ? 1 : 0;
  return n;
}

}  // namespace

double AnalyticCandela(const std::string& kind, double c, double g) {
  const double s = std::sin(g * kRad);
  if (kind == "axial") return 1200.0 * CosPow(g, 4) + 40.0 * CosPow(180 - g, 1);
  if (kind == "oval") {
    // Elliptical beam: 15 degrees across C0, 35 degrees across C90.
    const double cc = std::cos(c * kRad), sc = std::sin(c * kRad);
    const double inv_sigma2 = cc * cc / (15.0 * 15.0) + sc * sc / (35.0 * 35.0);
    return g >= 90 ? 0.0 : 2000.0 * std::exp(-0.5 * g * g * inv_sigma2);
  }
  if (kind == "wallwash") return 800.0 * CosPow(g, 1.5) * (1.0 + 0.8 * s * std::cos(c * kRad));
  if (kind == "side") return 600.0 * CosPow(g, 1) * (1.0 + 0.8 * s * std::sin(c * kRad));
  if (kind == "asym") {
    const double lobe = std::exp(-std::pow((g - 60.0) / 10.0, 2)) *
                        std::exp(-std::pow(AngleBetween(c, 200.0) / 25.0, 2));
    return 500.0 * CosPow(g, 2) * (1.0 + 0.7 * s * std::cos((c - 30.0) * kRad)) + 300.0 * lobe;
  }
  throw std::invalid_argument("AnalyticCandela: unknown kind '" + kind + "'");
}

double AnalyticTypeBFlood(double h_deg, double v_deg, double h_peak_deg) {
  const double dh = (h_deg - h_peak_deg) / 25, dv = (v_deg - 5) / 12;
  return 2000 * std::exp(-dh * dh - dv * dv);
}

std::string TypeBFloodIes(bool symmetric) {
  const std::vector<double> v = Steps(-90, 90, 2.5);
  const std::vector<double> h = symmetric ? Steps(0, 90, 2.5) : Steps(-90, 90, 2.5);
  const double h_peak = symmetric ? 0 : 10;
  std::string text = "IESNA:LM-63-2002\n[TEST] relight analytic fixture\n[MANUFAC] relight\n"
                     "[LUMINAIRE] relight analytic type B flood\nTILT=NONE\n";
  // lamps, lumens (-1: absolute), multiplier, #V, #H, type 2 (B), metres, opening 0.3 x 0.2 x 0.15.
  text += "1 -1 1 " + std::to_string(v.size()) + " " + std::to_string(h.size()) + " 2 2 0.3 0.2 0.15\n";
  text += "1 1 150\n";
  const auto list = [&text](const std::vector<double>& values) {
    char buf[32];
    for (size_t i = 0; i < values.size(); ++i) {
      std::snprintf(buf, sizeof buf, "%g", values[i]);
      text += buf;
      text += (i + 1) % 10 == 0 || i + 1 == values.size() ? "\n" : " ";
    }
  };
  list(v);
  list(h);
  for (double hh : h) {
    std::vector<double> row;
    for (double vv : v) row.push_back(std::round(AnalyticTypeBFlood(hh, vv, h_peak) * 100) / 100);
    list(row);
  }
  return text;
}

std::vector<PhotometricFixture> PhotometricFixtures() {
  const std::vector<double> g_full = Steps(0, 180, 2.5), g_down = Steps(0, 90, 2.5);
  std::vector<PhotometricFixture> out;
  out.push_back(Ies("ies_1986_axial.ies", "LM-63-1986",
                    Sample("axial", CSymmetry::kAxial, {0}, g_full, -1, 1)));
  out.push_back(Ies("ies_1991_quadrant.ies", "LM-63-1991",
                    Sample("oval", CSymmetry::kQuadrant, Steps(0, 90, 10), g_down, 2000, 1)));
  // A candela multiplier that the reader must apply.
  PhotometricTable wash = Sample("wallwash", CSymmetry::kBilateral, Steps(0, 180, 10), g_full, 1500, 1);
  wash.multiplier = 2.0;
  out.push_back(Ies("ies_1995_bilateral.ies", "LM-63-1995", wash));
  out.push_back(Ies("ies_2002_bilateral90.ies", "LM-63-2002",
                    Sample("side", CSymmetry::kBilateral90, Steps(90, 270, 10), g_full, 1200, 1)));
  out.push_back(Ies("ies_2019_full.ies", "LM-63-2019",
                    Sample("asym", CSymmetry::kNone, Steps(0, 360, 10), g_full, 1000, 1)));
  PhotometricTable tilted = Sample("oval", CSymmetry::kQuadrant, Steps(0, 90, 15), g_down, 2000, 1);
  tilted.tilt_data.lamp_geometry = 1;
  tilted.tilt_data.angle_deg = {0, 15, 30, 45, 60, 75, 90};
  tilted.tilt_data.factor = {1, 0.98, 0.95, 0.9, 0.86, 0.82, 0.8};
  out.push_back(Ies("ies_2002_tilt_include.ies", "LM-63-2002", tilted));

  const std::vector<double> gl = Steps(0, 180, 5);
  out.push_back(Ldt("ldt_isym0_none.ldt", Sample("asym", CSymmetry::kNone, Steps(0, 350, 10), gl, 1000, 1)));
  out.push_back(Ldt("ldt_isym1_axial.ldt", Sample("axial", CSymmetry::kAxial, {0}, gl, 1000, 1)));
  out.push_back(Ldt("ldt_isym2_c0_c180.ldt",
                    Sample("wallwash", CSymmetry::kBilateral, Steps(0, 180, 10), gl, 1000, 1)));
  out.push_back(Ldt("ldt_isym3_c90_c270.ldt",
                    Sample("side", CSymmetry::kBilateral90, Steps(90, 270, 10), gl, 1000, 1)));
  out.push_back(Ldt("ldt_isym4_quadrant.ldt",
                    Sample("oval", CSymmetry::kQuadrant, Steps(0, 90, 10), gl, 1000, 1)));
  return out;
}

std::vector<MalformedFixture> MalformedPhotometricFixtures() {
  const std::vector<PhotometricFixture> good = PhotometricFixtures();
  const std::string ies = good[2].text;  // LM-63-1995, bilateral, wrapped lines
  const std::string ldt = good[8].text;  // EULUMDAT Isym 2
  std::vector<MalformedFixture> out;
  {
    const std::string cut = ies.substr(0, ies.size() * 3 / 4);
    const std::string text = cut.substr(0, cut.find_last_of(' '));
    out.push_back({"ies_truncated.ies", text, "but the file ends", CountLines(text) + 1});
  }
  {
    // The data line says 72 vertical angles where 73 follow.
    const std::string text = ReplaceAfter(ies, "TILT=NONE", " 73 19 ", " 72 19 ");
    out.push_back({"ies_wrong_count.ies", text, "horizontal angles must increase strictly", 0});
  }
  {
    const std::string text = ReplaceAfter(ies, "TILT=NONE", " 73 19 ", " 73 20 ");
    out.push_back({"ies_count_too_high.ies", text, "horizontal angle 20 is", 0});
  }
  {
    // One candela value with a letter O for a zero.
    const size_t at = ies.rfind("\n", ies.size() - 2);
    std::string text = ies;
    text.insert(at + 1, "12O ");
    out.push_back({"ies_non_numeric.ies", text, "got '12O'", LineOf(text, at + 1)});
  }
  {
    // Issue 17: counts a header declares are checked against the values
    // present before anything is sized from them (this asked for ~80 GB).
    const std::string text = ReplaceAfter(ies, "TILT=NONE", " 73 19 ", " 10000 10000 ");
    out.push_back({"ies_huge_counts.ies", text, "(10000 vertical, 10000 horizontal) on line 6 declares 20000 values, but the file ends after 1479", 0});
  }
  {
    // Issue 17: a named file that never ends (or a FIFO) is refused, not read.
    const std::string text = ReplaceAfter(ies, "[LUMINAIRE]", "TILT=NONE", "TILT=/dev/zero");
    out.push_back({"ies_tilt_dev_zero.ies", text,
                   "'/dev/zero' is a character device, not a regular file", 5});
  }
  {
    const std::string text = ReplaceAfter(ies, "[LUMINAIRE]", "TILT=NONE", "TILT=SOMETIMES");
    out.push_back({"ies_bad_tilt_file.ies", text, "cannot read the tilt file", 0});
  }
  {
    const std::string tilted = good[5].text;
    const std::string text = ReplaceAfter(tilted, "TILT=INCLUDE", "\n1\n", "\n7\n");
    out.push_back({"ies_bad_tilt_geometry.ies", text, "TILT lamp-to-luminaire geometry", 0});
  }
  {
    const std::string text = ReplaceAfter(ies, "[LUMINAIRE]", "TILT=NONE", "TILTED NONE");
    out.push_back({"ies_no_tilt.ies", text, "no TILT= line", 0});
  }
  {
    const std::string text = ReplaceAfter(ies, "TILT=NONE", " 1 2 0 0 0", " 3 2 0 0 0");
    out.push_back({"ies_type_a.ies", text, "photometric type A is not supported", 0});
  }
  {
    // Type B with a type C file's vertical angles (0..180): past 90 is out of range.
    const std::string text = ReplaceAfter(ies, "TILT=NONE", " 1 2 0 0 0", " 2 2 0 0 0");
    out.push_back({"ies_type_b_angles.ies", text, "expected an angle in [-90, 90] degrees", 0});
  }
  {
    const std::string text = ldt.substr(0, ldt.size() * 2 / 3);
    out.push_back({"ldt_truncated.ldt", text.substr(0, text.rfind("\r\n") + 2), "but the file ends", 0});
  }
  {
    std::string text = ldt;
    text.replace(text.find("\r\n2\r\n") + 2, 1, "7");  // Isym on line 3
    out.push_back({"ldt_bad_isym.ldt", text, "symmetry indicator Isym", 3});
  }
  {
    // Line 6 (Ng) one too high: the intensities run out.
    std::string text = ldt;
    size_t at = 0;
    for (int line = 1; line < 6; ++line) at = text.find("\r\n", at) + 2;
    const size_t end = text.find("\r\n", at);
    text.replace(at, end - at, std::to_string(std::stoi(text.substr(at, end - at)) + 1));
    out.push_back({"ldt_wrong_count.ldt", text, "gamma angles must increase strictly", 0});
  }
  {
    // Mc (line 4) and Ng (line 6) far beyond the values the file holds.
    std::string text = ldt;
    size_t at = 0;
    for (int line = 1; line < 4; ++line) at = text.find("\r\n", at) + 2;
    text.replace(at, text.find("\r\n", at) - at, "10000");
    at = text.find("\r\n", text.find("\r\n", at) + 2) + 2;
    text.replace(at, text.find("\r\n", at) - at, "10000");
    out.push_back({"ldt_huge_counts.ldt", text, "Ng = 10000 gamma angles on line 4 declares 20000 values, but the file ends after", 0});
  }
  {
    std::string text = ldt;
    const size_t at = text.rfind("\r\n", text.size() - 3);
    text.replace(at + 2, text.size() - at - 4, "n/a");
    out.push_back({"ldt_non_numeric.ldt", text, "got 'n/a'", CountLines(text)});
  }
  return out;
}

}  // namespace relight::baker
