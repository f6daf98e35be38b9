// relight-solver-compare: the hierarchical radiosity solver against the dense
// one on the same scene and mesh. Builds both, solves the float64 reference
// at several aims with each, and prints the differences (relative to the
// dense solution's peak) and both solvers' times, as Markdown for
// docs/performance.md.
//
//   relight-solver-compare fixtures/living_room.toml [--patch-size 0.3] [--link-epsilon 2e-4]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "baker_core.h"
#include "reference.h"
#include "surface_agreement.h"
#include "relight/baker/baker.h"
#include "relight/baker/photometry.h"
#include "relight/baker/scene.h"

namespace {

using namespace relight::baker;
using Clock = std::chrono::steady_clock;

constexpr double kPi = 3.14159265358979323846;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

struct Case {
  std::string label;
  std::vector<FixtureSetting> settings;
};

std::vector<Case> Cases(const Scene& scene) {
  std::vector<FixtureSetting> defaults;
  for (const Luminaire& l : scene.luminaires)
    defaults.push_back(FixtureSetting{l.pan_deg, l.tilt_deg, l.dimmer, l.colour});
  std::vector<Case> cases{{"scene defaults", defaults}};
  for (const auto& [pan, tilt] : {std::pair<double, double>{0, 30}, {45, 60}}) {
    Case c{"pan " + std::to_string(int(pan)) + ", tilt " + std::to_string(int(tilt)), defaults};
    for (FixtureSetting& s : c.settings) {
      s.pan_deg = pan;
      s.tilt_deg = tilt;
    }
    cases.push_back(c);
  }
  return cases;
}

// Exact direct luminance rho E / pi at each vertex (the same in both solves);
// it only sets the indirect part's peak, so a (C, gamma) LID's C-average will do.
std::vector<Rgb> DirectVertexLuminance(const BakerCore& core,
                                       const std::vector<FixtureSetting>& settings) {
  std::vector<Rgb> out(core.mesh.vertex_count(), Rgb{0, 0, 0});
  for (size_t l = 0; l < settings.size(); ++l) {
    const Luminaire& lum = core.scene.luminaires[l];
    const Vec3 axis = BeamAxis(lum.mounting, settings[l].pan_deg, settings[l].tilt_deg);
    for (size_t v = 0; v < out.size(); ++v) {
      const DirectGeometry& d = core.direct[l].vertices[v];
      if (d.g_m2 <= 0) continue;
      const double e = d.g_m2 * ExactIntensity(lum.lid, axis, d.direction) * settings[l].dimmer;
      for (int c = 0; c < 3; ++c)
        out[v][c] += core.mesh.vertex_reflectance[v][c] * e * settings[l].colour[c] / kPi;
    }
  }
  return out;
}

struct Difference {
  double peak = 0, max_rel = 0, mean_rel = 0;
};

// |got - want| over receivers and channels, relative to want's peak; `minus`
// (same size, or empty) is subtracted from both first.
Difference Compare(const std::vector<Rgb>& got, const std::vector<Rgb>& want,
                   const std::vector<Rgb>& minus) {
  Difference d;
  double worst = 0, sum = 0;
  for (size_t k = 0; k < want.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      const double m = minus.empty() ? 0.0 : minus[k][c];
      d.peak = std::max(d.peak, std::abs(want[k][c] - m));
      const double e = std::abs(got[k][c] - want[k][c]);
      worst = std::max(worst, e);
      sum += e;
    }
  }
  if (d.peak > 0) {
    d.max_rel = worst / d.peak;
    d.mean_rel = sum / (3.0 * static_cast<double>(want.size())) / d.peak;
  }
  return d;
}

std::vector<Rgb> Concat(const std::vector<std::vector<Rgb>>& grids) {
  std::vector<Rgb> out;
  for (const auto& g : grids) out.insert(out.end(), g.begin(), g.end());
  return out;
}

// Per surface, at the scene's defaults: the hierarchical vertex luminance
// against the dense one, relative to each surface's peak (a bias shows as a
// signed mean of one sign on every surface).
void PrintSurfaceTable(const BakerCore& dense, const BakerCore& hier,
                       const std::vector<FixtureSetting>& settings) {
  const ReferenceResult want = ComputeReference(dense, settings);
  const ReferenceResult got = ComputeReference(hier, settings);
  std::printf("\nPer surface, scene defaults (hierarchical - dense, %% of the surface's peak; "
              "%d sweeps):\n\n| surface | peak cd/m^2 | mean signed | mean abs | max abs |\n"
              "| --- | ---: | ---: | ---: | ---: |\n",
              hier.hierarchical_solver ? hier.hierarchical_solver->max_sweeps_used() : 0);
  for (const SurfaceAgreement& a :
       CompareBySurface(dense.scene, dense.mesh, got.vertex_luminance, want.vertex_luminance)) {
    std::printf("| %s | %.4g | %+.3f%% | %.3f%% | %.3f%% |\n", a.name.c_str(), a.peak,
                100 * a.mean_signed, 100 * a.mean_abs, 100 * a.max_abs);
  }
}

int Run(const std::string& path, double patch_size_m, double epsilon, double tolerance,
        int threads, bool adaptive_visibility, bool absolute_links) {
  Scene scene = LoadScene(path);
  if (patch_size_m > 0) scene.patch_size_m = patch_size_m;
  BakeOptions dense_options;
  dense_options.threads = threads;
  dense_options.solver = SolverKind::kDense;
  BakeOptions hier_options = dense_options;
  hier_options.solver = SolverKind::kHierarchical;
  hier_options.link_epsilon = epsilon;
  hier_options.adaptive_visibility = adaptive_visibility;
  hier_options.receiver_relative_links = !absolute_links;
  if (tolerance > 0) hier_options.solve_tolerance = tolerance;

  auto t = Clock::now();
  const auto dense = BuildBakerCore(scene, dense_options, nullptr);
  const double dense_build_s = Seconds(t);
  t = Clock::now();
  const auto hier = BuildBakerCore(scene, hier_options, nullptr);
  const double hier_build_s = Seconds(t);

  std::printf("\n### %s, patch size %.3f m, link epsilon %g\n\n", scene.name.c_str(),
              scene.patch_size_m, epsilon);
  std::printf("%zu patches; hierarchical: %zu nodes, %zu links (%.2f per patch, dense pairs %.0f "
              "per patch)\n\n",
              dense->mesh.patch_count(), hier->report.nodes, hier->report.links,
              double(hier->report.links) / double(dense->mesh.patch_count()),
              double(dense->mesh.patch_count() - 1) / 2);
  std::printf(
      "| aim | vertex max | vertex mean | vertex indirect max | grid max | grid indirect max "
      "| dense solve s | hierarchical solve s |\n");
  std::printf("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n");
  double dense_solve_s = 0, hier_solve_s = 0;
  for (const Case& c : Cases(scene)) {
    t = Clock::now();
    const ReferenceResult want = ComputeReference(*dense, c.settings);
    const double ds = Seconds(t);
    t = Clock::now();
    const ReferenceResult got = ComputeReference(*hier, c.settings);
    const double hs = Seconds(t);
    dense_solve_s += ds;
    hier_solve_s += hs;
    const std::vector<Rgb> direct = DirectVertexLuminance(*dense, c.settings);
    const Difference v = Compare(got.vertex_luminance, want.vertex_luminance, {});
    const Difference vi = Compare(got.vertex_luminance, want.vertex_luminance, direct);
    const std::vector<Rgb> grid_want = Concat(want.grid_illuminance);
    const Difference g = Compare(Concat(got.grid_illuminance), grid_want, {});
    const Difference gi =
        Compare(Concat(got.grid_illuminance), grid_want, Concat(want.grid_direct_illuminance));
    std::printf("| %s | %.3f%% | %.4f%% | %.2f%% | %.3f%% | %.2f%% | %.3f | %.3f |\n",
                c.label.c_str(), 100 * v.max_rel, 100 * v.mean_rel, 100 * vi.max_rel,
                100 * g.max_rel, 100 * gi.max_rel, ds, hs);
  }
  PrintSurfaceTable(*dense, *hier, Cases(scene).front().settings);
  std::printf("\nErrors relative to the dense solution's peak (indirect: relative to the peak of "
              "the indirect part alone).\nCore build (mesh, rays, form factors or links, "
              "factorisation): dense %.2f s, hierarchical %.2f s (ratio %.3f); solves: dense %.3f "
              "s, hierarchical %.3f s (ratio %.3f).\n",
              dense_build_s, hier_build_s, hier_build_s / dense_build_s, dense_solve_s,
              hier_solve_s, hier_solve_s / dense_solve_s);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"relight-solver-compare: hierarchical vs dense radiosity on one scene",
               "relight-solver-compare"};
  std::string scene;
  double patch_size_m = 0;
  double epsilon = BakeOptions().link_epsilon;
  int threads = 0;
  double tolerance = 0;
  app.add_option("scene", scene, "scene file (.toml)")->required();
  app.add_option("--patch-size", patch_size_m, "patch edge, m (default: the scene's)")
      ->check(CLI::PositiveNumber);
  app.add_option("--link-epsilon", epsilon, "hierarchical refinement threshold")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--tolerance", tolerance,
                 "hierarchical solve tolerance (default: BakeOptions::solve_tolerance)")
      ->check(CLI::PositiveNumber);
  app.add_option("--threads", threads, "worker threads (0 = all cores)")
      ->check(CLI::Range(0, 1024));
  bool adaptive_visibility = false;
  app.add_flag("--adaptive-visibility", adaptive_visibility,
               "256 visibility rays where a node pair's 16 disagree");
  bool absolute_links = false;
  app.add_flag("--absolute-links", absolute_links,
               "the absolute link bound alone (no receiver-relative refinement)");
  CLI11_PARSE(app, argc, argv);
  try {
    return Run(scene, patch_size_m, epsilon, tolerance, threads, adaptive_visibility,
               absolute_links);
  } catch (const SceneError& e) {
    std::fprintf(stderr, "relight-solver-compare: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "relight-solver-compare: error: %s\n", e.what());
    return 1;
  }
}
