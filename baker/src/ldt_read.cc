// ParseEulumdat: EULUMDAT (.ldt) files. Lines 1-26 sit at fixed positions;
// lamp data takes 6 x n lines for n lamp sets; then 10 direct ratios, the
// Mc C angles, the Ng gamma angles and the intensities (cd/klm) of the C
// planes the symmetry indicator Isym says are stored:
//   Isym 0: all Mc planes; 1: one plane; 2: C 0-180 (Mc/2 + 1);
//   3: C 90-270 (Mc/2 + 1, starting at C 90); 4: C 0-90 (Mc/4 + 1).
// CRLF line ends and decimal commas occur in the wild (PITFALLS.md).
#include <cmath>
#include <string>

#include "photometric_text.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/scene.h"

namespace relight::baker {
namespace {

// Limits (docs/photometry.md), far above any real file, and checked against
// the values actually present before anything is sized from them.
constexpr int kMaxPlanes = 10000;                // Mc and Ng each
constexpr size_t kMaxIntensities = 1000000;      // stored planes x Ng

class LdtLines {
 public:
  LdtLines(const std::vector<std::string>& lines, std::string path)
      : lines_(lines), path_(std::move(path)) {}

  // Line `n` (1-based) as text; missing lines are an error naming the field.
  const std::string& Text(size_t n, const std::string& what) const {
    if (n > lines_.size()) {
      throw SceneError(path_, static_cast<int>(lines_.size()),
                       "expected " + what + " on line " + std::to_string(n) +
                           ", but the file ends (truncated?)");
    }
    return lines_[n - 1];
  }
  double Number(size_t n, const std::string& what) const {
    const std::string& s = Text(n, what);
    double v = 0;
    if (!ParseNumber(s, /*decimal_comma=*/true, &v)) {
      throw SceneError(path_, static_cast<int>(n),
                       "expected " + what + " (a number), got '" + Trim(s) + "'");
    }
    return v;
  }
  int Integer(size_t n, const std::string& what, int lo, int hi) const {
    const double v = Number(n, what);
    if (v != std::floor(v) || v < lo || v > hi) {
      throw SceneError(path_, static_cast<int>(n),
                       "expected " + what + " (an integer " + std::to_string(lo) + ".." +
                           std::to_string(hi) + "), got '" + Trim(lines_[n - 1]) + "'");
    }
    return static_cast<int>(v);
  }

 private:
  const std::vector<std::string>& lines_;
  std::string path_;
};

}  // namespace

PhotometricTable ParseEulumdat(const std::string& text, const std::string& path) {
  PhotometricTable t;
  t.path = path;
  t.format = PhotometricFormat::kEulumdat;
  t.version = "EULUMDAT";
  t.tilt = "NONE";
  const std::vector<std::string> lines = SplitLines(text);
  if (lines.empty()) throw SceneError(path, 0, "empty file, expected a EULUMDAT file");
  const LdtLines f(lines, path);
  f.Integer(2, "type indicator Ityp (0-3)", 0, 3);
  const int isym = f.Integer(3, "symmetry indicator Isym (0-4)", 0, 4);
  const int mc = f.Integer(4, "number of C planes Mc", 1, kMaxPlanes);
  f.Number(5, "distance between C planes Dc");
  const int ng = f.Integer(6, "number of gamma angles Ng", 1, kMaxPlanes);
  f.Number(7, "distance between gamma angles Dg");
  t.luminaire = Trim(f.Text(9, "luminaire name"));
  for (size_t n = 13; n <= 21; ++n) f.Number(n, "luminaire dimension (line " + std::to_string(n) + ")");
  f.Number(22, "downward flux fraction DFF");
  f.Number(23, "light output ratio LORL");
  const double conversion = f.Number(24, "conversion factor for luminous intensities");
  if (!(conversion > 0)) {
    throw SceneError(path, 24, "conversion factor for luminous intensities must be > 0");
  }
  f.Number(25, "tilt of the luminaire during measurement");
  const int sets = f.Integer(26, "number of standard sets of lamps n", 1, 20);
  // 26a..26f: number of lamps, type, total flux, colour, CRI, watts; n lines each.
  const size_t flux_first = 27 + 2 * static_cast<size_t>(sets);
  double flux = 0;
  for (int s = 0; s < sets; ++s) {
    f.Text(27 + s, "number of lamps of set " + std::to_string(s + 1));
    const double lm = f.Number(flux_first + s, "total luminous flux of lamp set " +
                                                    std::to_string(s + 1) + " (lm)");
    if (!(lm > 0)) {
      throw SceneError(path, static_cast<int>(flux_first + s),
                       "lamp flux must be > 0 lm (intensities are per 1000 lm of it)");
    }
    flux += lm;
    f.Text(27 + 5 * static_cast<size_t>(sets) + s, "wattage of lamp set " + std::to_string(s + 1));
  }
  const size_t ratios_first = 27 + 6 * static_cast<size_t>(sets);
  for (size_t k = 0; k < 10; ++k) f.Number(ratios_first + k, "direct ratio " + std::to_string(k + 1));

  NumberStream in(lines, ratios_first + 10 - 1, path, /*decimal_comma=*/true);
  in.Require(static_cast<size_t>(mc) + static_cast<size_t>(ng),
             "Mc = " + std::to_string(mc) + " C angles and Ng = " + std::to_string(ng) +
                 " gamma angles",
             4);
  std::vector<double> all_c;
  for (int i = 0; i < mc; ++i) {
    const int line = in.line();
    const double c = in.Number("C angle " + std::to_string(i + 1) + " of " + std::to_string(mc));
    if (c < 0 || c >= 360 || (!all_c.empty() && !(c > all_c.back()))) {
      in.Fail(line, "C angle " + std::to_string(i + 1) + " is " + Fmt(c) +
                        ": C angles must increase strictly within [0, 360)");
    }
    all_c.push_back(c);
  }
  for (int i = 0; i < ng; ++i) {
    const int line = in.line();
    const double g = in.Number("gamma angle " + std::to_string(i + 1) + " of " + std::to_string(ng));
    if (g < 0 || g > 180 || (!t.gamma_deg.empty() && !(g > t.gamma_deg.back()))) {
      in.Fail(line, "gamma angle " + std::to_string(i + 1) + " is " + Fmt(g) +
                        ": gamma angles must increase strictly within [0, 180]");
    }
    t.gamma_deg.push_back(g);
  }

  // Which of the listed planes are stored.
  size_t first = 0, count = static_cast<size_t>(mc);
  double expect_first = all_c.front(), expect_last = all_c.back();
  switch (isym) {
    case 0: t.symmetry = CSymmetry::kNone; break;
    case 1: t.symmetry = CSymmetry::kAxial; count = 1; break;
    case 2: t.symmetry = CSymmetry::kBilateral; count = mc / 2 + 1; expect_first = 0; expect_last = 180; break;
    case 3: t.symmetry = CSymmetry::kBilateral90; first = mc / 4; count = mc / 2 + 1; expect_first = 90; expect_last = 270; break;
    case 4: t.symmetry = CSymmetry::kQuadrant; count = mc / 4 + 1; expect_first = 0; expect_last = 90; break;
  }
  if ((isym >= 2 && (mc % 4 != 0 && isym != 2)) || (isym == 2 && mc % 2 != 0) ||
      first + count > all_c.size()) {
    throw SceneError(path, 4, "Mc = " + std::to_string(mc) + " C planes do not fit symmetry Isym " +
                                  std::to_string(isym));
  }
  t.c_deg.assign(all_c.begin() + static_cast<std::ptrdiff_t>(first),
                 all_c.begin() + static_cast<std::ptrdiff_t>(first + count));
  if (isym >= 2 && (t.c_deg.front() != expect_first || t.c_deg.back() != expect_last)) {
    throw SceneError(path, 3, "Isym " + std::to_string(isym) + " stores C " +
                                  Fmt(expect_first) + "-" + Fmt(expect_last) +
                                  ", but those planes are C " + Fmt(t.c_deg.front()) +
                                  "-" + Fmt(t.c_deg.back()) +
                                  " (are Mc and the C angles right?)");
  }
  if (isym == 0 && t.c_deg.front() != 0) {
    throw SceneError(path, 3, "Isym 0: the C angles must start at 0");
  }
  const size_t n_intensities = count * static_cast<size_t>(ng);
  if (n_intensities > kMaxIntensities) {
    throw SceneError(path, 4, std::to_string(count) + " stored C planes x Ng = " +
                                  std::to_string(ng) + " make " + std::to_string(n_intensities) +
                                  " intensities, more than the limit of " +
                                  std::to_string(kMaxIntensities));
  }
  in.Require(n_intensities, std::to_string(count) + " C planes x " + std::to_string(ng) +
                                " intensities",
             4);
  t.candela.reserve(n_intensities);
  t.lamp_lumens = flux;
  t.multiplier = conversion * flux / 1000.0;
  for (size_t p = 0; p < count; ++p) {
    for (int g = 0; g < ng; ++g) {
      const std::string what = "intensity " + std::to_string(g + 1) + " of " + std::to_string(ng) +
                               " in C plane " + Fmt(t.c_deg[p]);
      const int line = in.line();
      const double v = in.Number(what);
      if (v < 0) in.Fail(line, what + " is negative (" + Fmt(v) + ")");
      t.candela.push_back(v * t.multiplier);
    }
  }
  in.ExpectEnd(std::to_string(count) + " C planes x " + std::to_string(ng) + " intensities");
  if (!(t.PeakCandela() > 0)) {
    throw SceneError(path, static_cast<int>(ratios_first + 10), "every intensity is 0: the file emits no light");
  }
  return t;
}

}  // namespace relight::baker
