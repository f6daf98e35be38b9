// relight-accuracy: bakes a scene, runs the fixed-point engine on the bake
// file, and compares vertex luminance and grid illuminance with the float64
// reference solve at several aims. Prints a Markdown table for docs/accuracy.md.
//
//   relight-accuracy fixtures/cornell_box.toml --direct both
#include <chrono>
#include <memory>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "relight/bake/bake.h"
#include "relight/baker/accuracy.h"
#include "relight/baker/baker.h"
#include "relight/baker/lid_error.h"
#include "relight/baker/scene.h"
#include "relight/engine/engine.h"

namespace {

using relight::baker::FixtureSetting;

struct Case {
  std::string label;
  std::vector<FixtureSetting> settings;
};

// Zooming beams at their narrowest, middle and widest angle (scene aims).
void AddZoomCases(const relight::baker::Scene& scene, const std::vector<FixtureSetting>& defaults,
                  std::vector<Case>* cases) {
  const char* labels[3] = {"narrowest zoom", "middle zoom", "widest zoom"};
  for (int i = 0; i < 3; ++i) {
    Case c{labels[i], defaults};
    bool any = false;
    for (size_t l = 0; l < scene.luminaires.size(); ++l) {
      const relight::baker::Lid& lid = scene.luminaires[l].lid;
      if (!lid.zooms()) continue;
      c.settings[l].zoom_deg = lid.zoom_min_deg + 0.5 * i * (lid.zoom_max_deg - lid.zoom_min_deg);
      any = true;
    }
    if (any) cases->push_back(c);
  }
}

std::vector<Case> StandardCases(const std::vector<FixtureSetting>& defaults) {
  std::vector<Case> cases;
  const auto with_aim = [&](const std::string& label, double pan, double tilt) {
    Case c{label, defaults};
    for (FixtureSetting& s : c.settings) {
      s.pan_deg = pan;
      s.tilt_deg = tilt;
    }
    cases.push_back(c);
  };
  cases.push_back({"scene defaults", defaults});
  with_aim("pan 0, tilt 0 (axis vertical)", 0, 0);
  with_aim("pan 0, tilt 30", 0, 30);
  with_aim("pan 45, tilt 60", 45, 60);
  return cases;
}

// The bake's solver and the reference's ("same": the bake's; "dense": the
// dense matrix, to measure a hierarchical bake against it).
struct Solvers {
  std::string bake = "auto", reference = "same";
};

relight::baker::SolverKind SolverOf(const std::string& name, relight::baker::SolverKind fallback) {
  if (name == "dense") return relight::baker::SolverKind::kDense;
  if (name == "hierarchical") return relight::baker::SolverKind::kHierarchical;
  return fallback;
}

int Run(const std::string& scene_path, relight::baker::DirectModeKind mode, const std::string& tmp_dir,
        double lid_error, double compress_error, const Solvers& solvers) {
  using Clock = std::chrono::steady_clock;
  relight::baker::Scene scene = relight::baker::LoadScene(scene_path);
  std::vector<relight::baker::LuminaireDegree> degrees;
  if (lid_error > 0) degrees = relight::baker::ApplyLidErrorTarget(&scene, lid_error, mode);
  relight::baker::BakeOptions options;
  options.direct_mode = mode;
  options.compress_error = compress_error;
  options.solver = SolverOf(solvers.bake, options.solver);
  const auto t0 = Clock::now();
  relight::baker::Baker baker(scene, options);
  // A reference of another solver: its own baker on the same scene and mesh options.
  std::unique_ptr<relight::baker::Baker> other_reference;
  if (solvers.reference != "same") {
    relight::baker::BakeOptions ref_options = options;
    ref_options.solver = SolverOf(solvers.reference, options.solver);
    other_reference = std::make_unique<relight::baker::Baker>(scene, ref_options);
  }
  const relight::Bake bake = baker.Bake();
  const double bake_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const std::string path = tmp_dir + "/relight-accuracy.rlb";
  if (relight::Status st = relight::WriteBake(bake, path); !st.ok()) {
    std::fprintf(stderr, "relight-accuracy: error: %s\n", st.ToString().c_str());
    return 1;
  }
  relight::Engine engine;
  if (relight::Status st = engine.Open(path); !st.ok()) {
    std::fprintf(stderr, "relight-accuracy: error: %s\n", st.ToString().c_str());
    return 1;
  }
  std::remove(path.c_str());
  const char* mode_name = mode == relight::baker::DirectModeKind::kExact ? "exact direct + SH indirect"
                                                                           : "all in SH (Dobashi)";
  std::printf("\n### %s — %s\n\n", scene.name.c_str(), mode_name);
  std::printf("%zu patches, %zu vertices, %zu grid points, %zu SH terms; bake %.1f s (%s solver)%s\n\n",
              baker.report().patches, baker.report().vertices, baker.report().grid_points,
              baker.report().sh_terms, bake_s,
              baker.report().solver == relight::baker::SolverKind::kHierarchical ? "hierarchical" : "dense",
              other_reference ? "; reference: the dense solve" : "");
  if (compress_error > 0) {
    const relight::baker::BakeReport& r = baker.report();
    std::printf("bases compressed (--compress-error %.3g%%): %.1fx vs float32, %zu of %zu; baker's estimate "
                "max %.2f%% / mean %.3f%% of peak\n\n",
                100 * compress_error,
                static_cast<double>(r.basis_float32_bytes) / static_cast<double>(r.basis_bytes),
                r.bases_compressed, r.bases, 100 * r.compress_max_error, 100 * r.compress_mean_error);
  }
  for (const auto& d : baker.report().zoom_degrees) {
    std::printf("%s: zoom: SH degree %d for its narrowest beam (%s LID error %.2f%%, window %s)\n\n",
                d.name.c_str(), d.choice.degree, relight::baker::LidErrorMeasureName(d.measure),
                100 * d.choice.error, relight::baker::ShWindowName(d.window));
  }
  if (!degrees.empty()) {
    std::printf("SH degrees from --lid-error %.3g%%:\n\n", 100 * lid_error);
    std::printf("| luminaire | measure | window | degree | LID error |\n| --- | --- | --- | ---: | ---: |\n");
    for (const auto& d : degrees) {
      std::printf("| %s | %s | %s | %d | %.2f%%%s |\n", d.name.c_str(),
                  relight::baker::LidErrorMeasureName(d.measure), relight::baker::ShWindowName(d.window),
                  d.choice.degree, 100 * d.choice.error, d.choice.met ? "" : " (target not met at the maximum degree)");
    }
    std::printf("\n");
  }
  std::printf("| aim | vertex peak cd/m² | vertex max err | vertex mean err | grid peak lux | grid max err | grid mean err |\n");
  std::printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  std::vector<Case> cases = StandardCases(baker.DefaultSettings());
  AddZoomCases(scene, baker.DefaultSettings(), &cases);
  for (const Case& c : cases) {
    const relight::baker::ReferenceResult ref =
        other_reference ? other_reference->Reference(c.settings) : baker.Reference(c.settings);
    const relight::baker::AccuracyReport r = relight::baker::CompareWithReference(&engine, ref, c.settings);
    std::printf("| %s | %.3f | %.3f%% | %.4f%% | %.2f | %.3f%% | %.4f%% |\n", c.label.c_str(), r.vertices.peak,
                100 * r.vertices.max_rel, 100 * r.vertices.mean_rel, r.grids.peak, 100 * r.grids.max_rel,
                100 * r.grids.mean_rel);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "relight-accuracy: bake a scene, run the fixed-point engine on the bake file and compare it with\n"
      "the float64 reference solve (exact luminous intensity distributions, no basis) at several aims.\n"
      "Errors are |engine - reference| / peak of the reference, over vertices x RGB (luminance, cd/m^2)\n"
      "and over calculation-grid points x RGB (illuminance, lux)."};
  std::string scene_path, direct = "both", tmp_dir = "/tmp";
  double lid_error_percent = 0, compress_error_percent = 0;
  app.add_option("scene", scene_path, "scene file (.toml)")->required();
  app.add_option("--direct", direct, "exact | sh | both")->check(CLI::IsMember({"exact", "sh", "both"}))->capture_default_str();
  app.add_option("--tmp", tmp_dir, "folder for the temporary bake file")->capture_default_str();
  app.add_option("--lid-error", lid_error_percent,
                 "choose each luminaire's SH degree for this LID error target, percent (as relight-bake)")
      ->check(CLI::Range(0.0, 100.0));
  app.add_option("--compress-error", compress_error_percent,
                 "compress the bases as relight-bake --compress-error does, percent (0: uncompressed)")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  Solvers solvers;
  app.add_option("--solver", solvers.bake, "the bake's radiosity solver, as relight-bake's")
      ->check(CLI::IsMember({"auto", "dense", "hierarchical"}))
      ->capture_default_str();
  app.add_option("--reference-solver", solvers.reference,
                 "solver of the reference: the bake's (same) or the dense matrix (dense: a hierarchical bake "
                 "against the exact solve of the same mesh)")
      ->check(CLI::IsMember({"same", "dense"}))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    if (direct != "sh") {
      if (int rc = Run(scene_path, relight::baker::DirectModeKind::kExact, tmp_dir, lid_error_percent / 100,
                       compress_error_percent / 100, solvers); rc != 0) return rc;
    }
    if (direct != "exact") {
      if (int rc = Run(scene_path, relight::baker::DirectModeKind::kAllInSh, tmp_dir, lid_error_percent / 100,
                       compress_error_percent / 100, solvers); rc != 0) return rc;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "relight-accuracy: error: %s\n", e.what());
    return 2;
  }
  return 0;
}
