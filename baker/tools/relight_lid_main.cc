// relight-lid: photometric files on the command line.
//
//   relight-lid info FILE.ies|FILE.ldt          what the reader sees (or the error)
//   relight-lid fixtures DIR                    write the project's analytic fixtures
//   relight-lid plot FILE -o lid.svg --degree 8 --window none,sigma
//                                               polar plot: file vs its SH series
//   relight-lid edit FILE --point 20=900 --point 90:45=100 -o OUT.ies
//                                               beam editing (Dobashi 4.1), saved
//   relight-lid degree FILE --lid-error 2       SH degree for an error target
#include <cstdio>
#include <fstream>
#include <string>

#include <CLI/CLI.hpp>

#include "relight/baker/analytic_photometry.h"
#include "relight/baker/beam_edit.h"
#include "relight/baker/lid_error.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/photometry.h"
#include "relight/baker/polar_plot.h"
#include "relight/baker/scene.h"
#include "relight/base/sh_index.h"

namespace {

using namespace relight::baker;

int Info(const std::string& path) {
  const PhotometricTable t = LoadPhotometricFile(path);
  std::printf("%s\n", path.c_str());
  std::printf("  format     %s %s, TILT=%s\n", t.format == PhotometricFormat::kIes ? "IES" : "EULUMDAT",
              t.version.c_str(), t.tilt.c_str());
  std::printf("  luminaire  %s\n", t.luminaire.c_str());
  std::printf("  type       %s\n", t.photometric_type == "B" ? "B (floodlight), resampled to C/gamma"
                                                                  : t.photometric_type.c_str());
  std::printf("  symmetry   %s\n", CSymmetryName(t.symmetry));
  std::printf("  planes     %zu (C %g..%g), gammas %zu (%g..%g)\n", t.planes(), t.c_deg.front(),
              t.c_deg.back(), t.gammas(), t.gamma_deg.front(), t.gamma_deg.back());
  std::printf("  peak       %.2f cd\n", t.PeakCandela());
  std::printf("  flux       %.1f lm (lamps %s)\n", t.LuminousFlux(),
              t.lamp_lumens > 0 ? (std::to_string(t.lamp_lumens) + " lm").c_str() : "absolute");
  std::printf("  multiplier %g\n", t.multiplier);
  return 0;
}

bool WriteText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) {
    std::fprintf(stderr, "relight-lid: error: cannot write %s\n", path.c_str());
    return false;
  }
  return true;
}

int Fixtures(const std::string& dir) {
  for (const PhotometricFixture& f : PhotometricFixtures()) {
    if (!WriteText(dir + "/" + f.file_name, f.text)) return 1;
    std::printf("%s/%s\n", dir.c_str(), f.file_name.c_str());
  }
  if (!WriteText(dir + "/" + kTypeBFloodFile, TypeBFloodIes(false))) return 1;
  std::printf("%s/%s\n", dir.c_str(), kTypeBFloodFile);
  for (const MalformedFixture& f : MalformedPhotometricFixtures()) {
    if (!WriteText(dir + "/malformed/" + f.file_name, f.text)) return 1;
    std::printf("%s/malformed/%s\n", dir.c_str(), f.file_name.c_str());
  }
  return 0;
}

std::vector<ShWindow> ParseWindows(const std::string& list) {
  std::vector<ShWindow> out;
  size_t start = 0;
  while (start <= list.size()) {
    const size_t comma = list.find(',', start);
    out.push_back(ParseShWindow(list.substr(start, comma - start)));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

int Plot(const std::string& path, const std::string& out, int degree, const std::string& windows) {
  PolarPlotOptions o;
  o.degree = degree;
  o.windows = ParseWindows(windows);
  o.title = path.substr(path.find_last_of('/') + 1) + ": SH degree " + std::to_string(degree);
  const std::string svg = LidPolarSvg(LoadLid(path), o);
  if (!WriteText(out, svg)) return 1;
  std::printf("relight-lid: wrote %s\n", out.c_str());
  return 0;
}

int Degree(const std::string& path, double percent) {
  const LidErrorModel model(LoadLid(path));
  std::printf("%s: smallest SH degree for a %.3g%% LID error\n", path.c_str(), percent);
  for (LidErrorMeasure m : {LidErrorMeasure::kZonalFlux, LidErrorMeasure::kL2}) {
    for (ShWindow w : {ShWindow::kNone, ShWindow::kSigma}) {
      const DegreeChoice c = ChooseShDegree(model, percent / 100, w, m);
      std::printf("  %-10s window %-6s degree %2d, error %.2f%%%s\n", LidErrorMeasureName(m),
                  ShWindowName(w), c.degree, 100 * c.error, c.met ? "" : " (not met at the maximum)");
    }
  }
  return 0;
}

// Beam editing: control points moved on the file's table, the Legendre
// weights of its axisymmetric part updated incrementally (Dobashi Eq. 21)
// and checked against a full recomputation (Eq. 19), the profile saved.
int Edit(const std::string& path, const std::vector<std::string>& points, double scale,
         const std::string& out, int degree) {
  PhotometricTable t = LoadPhotometricFile(path);
  constexpr int kM = 720;
  const std::vector<double> before = SampleLid(MakeLid(t), kM);
  for (double& cd : t.candela) cd *= scale;
  for (const std::string& text : points) ApplyControlPoint(ParseControlPoint(text), &t);
  const std::vector<double> after = SampleLid(MakeLid(t), kM);
  std::vector<double> w = LegendreWeights(before, degree);
  int moved = 0;
  for (int k = 0; k <= kM; ++k) {
    if (after[k] == before[k]) continue;
    UpdateLegendreWeights(&w, kM, k, before[k], after[k]);  // Eq. 21
    ++moved;
  }
  const std::vector<double> full = LegendreWeights(after, degree);
  const std::vector<double> old_w = LegendreWeights(before, degree);
  double worst = 0;
  std::printf("%d of %d samples moved; Legendre weights (cd) of the axisymmetric part:\n", moved, kM + 1);
  for (int l = 0; l <= degree; ++l) {
    std::printf("  w_%-2d %12.4f -> %12.4f\n", l, old_w[l], w[l]);
    worst = std::max(worst, std::abs(w[l] - full[l]));
  }
  std::printf("incremental (Eq. 21) vs full (Eq. 19): max difference %.3g cd\n", worst);
  const std::string ext = out.substr(out.find_last_of('.') + 1);
  const std::string text = ext == "ldt" || ext == "LDT" ? WriteEulumdat(t) : WriteIes(t, "LM-63-2002");
  if (!WriteText(out, text)) return 1;
  LoadPhotometricFile(out);  // what was written reads back
  std::printf("relight-lid: wrote %s\n", out.c_str());
  return 0;
}

// Markdown table: every window at several degrees for each file.
int Windows(const std::vector<std::string>& files) {
  std::printf("| file | N | window | zonal flux error | L2 error | lowest / peak |\n");
  std::printf("| --- | ---: | --- | ---: | ---: | ---: |\n");
  for (const std::string& path : files) {
    const LidErrorModel model(LoadLid(path));
    const std::string name = path.substr(path.find_last_of('/') + 1);
    for (int n : {4, 8, 12, 16}) {
      for (ShWindow w : {ShWindow::kNone, ShWindow::kSigma, ShWindow::kHanning, ShWindow::kLanczos,
                         ShWindow::kSloan}) {
        std::printf("| %s | %d | %s | %.2f%% | %.2f%% | %.2f%% |\n", name.c_str(), n, ShWindowName(w),
                    100 * model.Error(n, w, LidErrorMeasure::kZonalFlux),
                    100 * model.Error(n, w, LidErrorMeasure::kL2), 100 * model.MinimumRelative(n, w));
      }
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"relight-lid: photometric files (IES LM-63, EULUMDAT)"};
  app.require_subcommand(1);
  std::string file, dir;
  CLI::App* info = app.add_subcommand("info", "read a photometric file and describe it");
  info->add_option("file", file, ".ies or .ldt file")->required();
  CLI::App* fixtures = app.add_subcommand("fixtures", "write the analytic fixture files");
  fixtures->add_option("dir", dir, "folder (with a malformed/ folder inside)")->required();
  std::string out, windows = "none";
  int degree = 8;
  CLI::App* plot = app.add_subcommand("plot", "polar plot (SVG) of a file's distribution vs its SH series");
  plot->add_option("file", file, ".ies or .ldt file")->required();
  plot->add_option("-o,--output", out, "SVG file")->required();
  plot->add_option("--degree", degree, "SH degree N")->check(CLI::Range(0, relight::kMaxShDegree))->capture_default_str();
  plot->add_option("--window", windows, "comma-separated: none, sigma, hanning, lanczos, sloan")
      ->capture_default_str();
  std::vector<std::string> points;
  double scale = 1.0, percent = 2.0;
  CLI::App* edit = app.add_subcommand("edit", "move control points of a distribution and save it");
  edit->add_option("file", file, ".ies or .ldt file")->required();
  edit->add_option("--point", points, "GAMMA=CD (every plane) or C:GAMMA=CD (one stored plane); repeatable");
  edit->add_option("--scale", scale, "multiply every intensity first")->check(CLI::Range(0.0, 1e6));
  edit->add_option("--degree", degree, "Legendre degree to report")->check(CLI::Range(0, relight::kMaxShDegree))->capture_default_str();
  edit->add_option("-o,--output", out, "output .ies (LM-63-2002) or .ldt")->required();
  CLI::App* deg = app.add_subcommand("degree", "SH degree a file needs for an error target");
  deg->add_option("file", file, ".ies or .ldt file")->required();
  deg->add_option("--lid-error", percent, "target, percent")->check(CLI::Range(0.001, 100.0))->capture_default_str();
  std::vector<std::string> files;
  CLI::App* win = app.add_subcommand("windows", "compare SH windows (Markdown table) for files");
  win->add_option("files", files, ".ies or .ldt files")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    if (*win) return Windows(files);
    if (*info) return Info(file);
    if (*fixtures) return Fixtures(dir);
    if (*plot) return Plot(file, out, degree, windows);
    if (*edit) return Edit(file, points, scale, out, degree);
    if (*deg) return Degree(file, percent);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "relight-lid: error: %s\n", e.what());
    return 2;
  }
  return 0;
}
