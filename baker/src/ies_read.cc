// ParseIes: IES LM-63 photometric files, every header generation (1986 with
// no identifier line, IESNA91, IESNA:LM-63-1995 / "IESNA95", -2002,
// IES:LM-63-2019), TILT=NONE / INCLUDE / <file>, photometric type C with any
// horizontal symmetry, and type B (floodlights), resampled to type C
// (type_b_photometry.h). After the TILT line the data is a stream of numbers
// separated by blanks or commas over any number of lines (PITFALLS.md).
#include <algorithm>
#include <cmath>
#include "bounded_read.h"
#include "photometric_text.h"
#include "type_b_photometry.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/scene.h"

namespace relight::baker {
namespace {

// Limits (docs/photometry.md), far above any real file (a 0.5-degree full
// table is 361 x 721 = 260281 values) and checked, like every count, against
// the values actually present before anything is sized from them.
constexpr int kMaxAngles = 10000;               // per axis, and TILT angles
constexpr size_t kMaxCandelaValues = 1000000;   // vertical x horizontal

std::string Upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string VersionOf(const std::string& first_line) {
  const std::string s = Upper(Trim(first_line));
  if (s.rfind("IESNA:LM-63-", 0) == 0) return s.substr(6);
  if (s.rfind("IES:LM-63-", 0) == 0) return s.substr(4);
  if (s == "IESNA91") return "LM-63-1991";
  if (s == "IESNA95") return "LM-63-1995";  // an early spelling (Radiance's examp1.ies)
  return "LM-63-1986";                      // no identifier line
}

// `count` strictly increasing angles within [lo, hi].
std::vector<double> ReadAngles(NumberStream* in, int count, const char* what, double lo,
                               double hi) {
  std::vector<double> out;
  out.reserve(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const int line = in->line();
    const double a = in->Number(std::string(what) + " " + std::to_string(i + 1) + " of " +
                               std::to_string(count));
    if (a < lo || a > hi) {
      in->Fail(line, std::string(what) + " " + std::to_string(i + 1) + " is " + Fmt(a) +
                         ", expected an angle in [" + std::to_string(static_cast<int>(lo)) + ", " +
                         std::to_string(static_cast<int>(hi)) + "] degrees");
    }
    if (!out.empty() && !(a > out.back())) {
      in->Fail(line, std::string(what) + "s must increase strictly: " + Fmt(a) +
                         " follows " + Fmt(out.back()) +
                         " (is the angle count right?)");
    }
    out.push_back(a);
  }
  return out;
}

void ReadTilt(NumberStream* in, TiltData* tilt) {
  tilt->lamp_geometry = in->Integer("TILT lamp-to-luminaire geometry", 1, 3);
  const int count_line = in->line();
  const int n = in->Integer("TILT angle count", 1, kMaxAngles);
  in->Require(2 * static_cast<size_t>(n),
              "TILT angle count " + std::to_string(n) + " (angles and factors)", count_line);
  tilt->angle_deg = ReadAngles(in, n, "TILT angle", 0, 180);
  for (int i = 0; i < n; ++i) {
    const int line = in->line();
    const double f = in->Number("TILT multiplying factor " + std::to_string(i + 1) + " of " +
                                std::to_string(n));
    if (f < 0) in->Fail(line, "TILT multiplying factors must be >= 0, got " + Fmt(f));
    tilt->factor.push_back(f);
  }
}

CSymmetry SymmetryOf(const std::vector<double>& h, NumberStream* in, int line) {
  if (h.size() == 1) return CSymmetry::kAxial;
  const double first = h.front(), last = h.back();
  if (first == 0 && last == 90) return CSymmetry::kQuadrant;
  if (first == 0 && last == 180) return CSymmetry::kBilateral;
  if (first == 0 && last == 360) return CSymmetry::kNone;
  if (first == 90 && last == 270) return CSymmetry::kBilateral90;
  in->Fail(line, "horizontal angles run from " + Fmt(first) + " to " +
                     Fmt(last) +
                     "; type C expects one angle, or 0-90, 0-180, 90-270 or 0-360 degrees");
}

}  // namespace

PhotometricTable ParseIes(const std::string& text, const std::string& path) {
  PhotometricTable t;
  t.path = path;
  t.format = PhotometricFormat::kIes;
  const std::vector<std::string> lines = SplitLines(text);
  if (lines.empty()) throw SceneError(path, 0, "empty file, expected an IES LM-63 photometric file");
  t.version = VersionOf(lines[0]);

  size_t tilt_line = lines.size();
  for (size_t i = 0; i < lines.size(); ++i) {
    const std::string s = Trim(lines[i]);
    if (Upper(s).rfind("TILT", 0) == 0 && s.find('=') != std::string::npos) {
      tilt_line = i;
      break;
    }
    // Keep the luminaire's description for reports.
    const std::string u = Upper(s);
    if (u.rfind("[LUMINAIRE]", 0) == 0 && t.luminaire.empty()) t.luminaire = Trim(s.substr(11));
    if (u.rfind("[LUMCAT]", 0) == 0 && t.luminaire.empty()) t.luminaire = Trim(s.substr(8));
  }
  if (tilt_line == lines.size()) {
    throw SceneError(path, static_cast<int>(lines.size()),
                     "no TILT= line: expected TILT=NONE, TILT=INCLUDE or TILT=<file> between the "
                     "header and the photometric data");
  }
  const std::string tilt_text = Trim(lines[tilt_line]);
  t.tilt = Trim(tilt_text.substr(tilt_text.find('=') + 1));
  const int tilt_line_no = static_cast<int>(tilt_line) + 1;
  NumberStream in(lines, tilt_line + 1, path, /*decimal_comma=*/false);

  if (Upper(t.tilt) == "NONE") {
    t.tilt = "NONE";
  } else if (Upper(t.tilt) == "INCLUDE") {
    t.tilt = "INCLUDE";
    ReadTilt(&in, &t.tilt_data);
  } else if (t.tilt.empty()) {
    throw SceneError(path, tilt_line_no, "TILT= has no value: expected NONE, INCLUDE or a file name");
  } else {
    // TILT=<file>: the tilt data lives in a file beside this one.
    const size_t slash = path.find_last_of('/');
    const std::string tilt_path =
        t.tilt[0] == '/' ? t.tilt
                         : (slash == std::string::npos ? std::string() : path.substr(0, slash + 1)) +
                               t.tilt;
    std::string tilt_file_text, why;
    if (!ReadBoundedFile(tilt_path, kMaxPhotometricFileBytes, &tilt_file_text, &why)) {
      throw SceneError(path, tilt_line_no,
                       "TILT=" + t.tilt + ": cannot read the tilt file: " + why +
                           " (expected NONE, INCLUDE or an existing file)");
    }
    const std::vector<std::string> tilt_lines = SplitLines(tilt_file_text);
    NumberStream tilt_in(tilt_lines, 0, tilt_path, false);
    ReadTilt(&tilt_in, &t.tilt_data);
  }

  const int lamps = in.Integer("number of lamps", 1, 1000000);
  const int lumens_line = in.line();
  const double lumens_per_lamp = in.Number("lumens per lamp (-1 for absolute photometry)");
  if (!(lumens_per_lamp > 0) && lumens_per_lamp != -1) {
    in.Fail(lumens_line, "lumens per lamp must be > 0 or -1 (absolute photometry), got " +
                             Fmt(lumens_per_lamp));
  }
  const int multiplier_line = in.line();
  const double multiplier = in.Number("candela multiplier");
  if (!(multiplier > 0)) {
    in.Fail(multiplier_line, "candela multiplier must be > 0, got " + Fmt(multiplier));
  }
  const int counts_line = in.line();
  const int n_vertical = in.Integer("number of vertical angles", 1, kMaxAngles);
  const int n_horizontal = in.Integer("number of horizontal angles", 1, kMaxAngles);
  const int type_line = in.line();
  const int type = in.Integer("photometric type (1 = C, 2 = B, 3 = A)", 1, 3);
  if (type == 3) {
    in.Fail(type_line, "photometric type A is not supported: relight reads type C (1) and type B (2) files");
  }
  const bool type_b = type == 2;
  in.Integer("units type (1 = feet, 2 = metres)", 1, 2);
  for (const char* what : {"luminous opening width", "luminous opening length",
                           "luminous opening height"}) {
    in.Number(what);
  }
  const int ballast_line = in.line();
  const double ballast = in.Number("ballast factor");
  const double lamp_factor = in.Number("ballast-lamp photometric factor (future use)");
  if (!(ballast > 0) || !(lamp_factor > 0)) {
    in.Fail(ballast_line, "ballast factor and ballast-lamp factor must be > 0");
  }
  in.Number("input watts");

  t.multiplier = multiplier * ballast * lamp_factor;
  t.lamp_lumens = lumens_per_lamp > 0 ? lamps * lumens_per_lamp : 0;
  in.Require(static_cast<size_t>(n_vertical) + static_cast<size_t>(n_horizontal),
             "the angle counts (" + std::to_string(n_vertical) + " vertical, " +
                 std::to_string(n_horizontal) + " horizontal)",
             counts_line);
  std::vector<double> vertical =
      ReadAngles(&in, n_vertical, "vertical angle", type_b ? -90 : 0, type_b ? 90 : 180);
  const int h_line = in.line();
  std::vector<double> horizontal =
      ReadAngles(&in, n_horizontal, "horizontal angle", type_b ? -90 : 0, type_b ? 90 : 360);
  if (type_b && (n_vertical < 2 || n_horizontal < 2)) {
    in.Fail(h_line, "a type B file needs at least 2 vertical and 2 horizontal angles, got " +
                        std::to_string(n_vertical) + " and " + std::to_string(n_horizontal));
  }
  if (!type_b) t.symmetry = SymmetryOf(horizontal, &in, h_line);
  const size_t n_candela = static_cast<size_t>(n_vertical) * static_cast<size_t>(n_horizontal);
  if (n_candela > kMaxCandelaValues) {
    in.Fail(counts_line, std::to_string(n_vertical) + " vertical x " + std::to_string(n_horizontal) +
                        " horizontal angles make " + std::to_string(n_candela) +
                        " candela values, more than the limit of " +
                        std::to_string(kMaxCandelaValues));
  }
  in.Require(n_candela, std::to_string(n_horizontal) + " x " + std::to_string(n_vertical) +
                            " candela table",
             counts_line);
  std::vector<double> candela;
  candela.reserve(static_cast<size_t>(n_vertical) * static_cast<size_t>(n_horizontal));
  for (int h = 0; h < n_horizontal; ++h) {
    for (int v = 0; v < n_vertical; ++v) {
      const std::string what = "candela value " + std::to_string(v + 1) + " of " +
                               std::to_string(n_vertical) + " in horizontal plane " +
                               std::to_string(h + 1) + " of " + std::to_string(n_horizontal);
      const int line = in.line();
      const double cd = in.Number(what);
      if (cd < 0) in.Fail(line, what + " is negative (" + Fmt(cd) + ")");
      candela.push_back(cd * t.multiplier);
    }
  }
  in.ExpectEnd(std::to_string(n_horizontal) + " x " + std::to_string(n_vertical) +
               " candela values");
  if (type_b) {
    t.photometric_type = "B";
    ConvertTypeBToC(TypeBTable{std::move(horizontal), std::move(vertical), std::move(candela)}, &t);
  } else {
    t.gamma_deg = std::move(vertical);
    t.c_deg = std::move(horizontal);
    t.candela = std::move(candela);
  }
  if (!(t.PeakCandela() > 0)) {
    throw SceneError(path, tilt_line_no + 1, "every candela value is 0: the file emits no light");
  }
  return t;
}

}  // namespace relight::baker
