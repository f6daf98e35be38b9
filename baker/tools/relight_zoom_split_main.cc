// relight-zoom-split: where a narrow zoom's grid error comes from (issue 12),
// in float64, without the engine. The scene's first zooming luminaire alone,
// at its scene aim and the given beam angle; its grid illuminance split as
//   direct     exact at the point (the engine's exact direct term),
//   first hop  gather x (rho E): light that reflected once,
//   later      gather x (M - rho E): light that reflected twice or more
//              (and of it the second hop, gather x rho F (rho E)),
// each computed from the exact beam (the reference) and from its degree-N
// Legendre series (what an SH basis of degree N carries, undamped as in the
// exact-direct mode). Errors are |series - exact| / the grid's peak total
// (green channel), max and mean over the points of the first grid; "exact
// hop" rows replace the series' first hop with the exact one (the route of
// computing the first bounce from the exact direct light).
//
//   relight-zoom-split fixtures/cornell_zoom.toml --zoom 11 --degrees 16,20,24
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "baker_core.h"
#include "reference.h"
#include "relight/baker/beam_profile.h"
#include "relight/baker/lid_error.h"
#include "relight/baker/scene.h"

namespace {

using relight::baker::Lid;
constexpr double kPi = 3.14159265358979323846;

// The degree-n Legendre series of an axisymmetric LID (Dobashi Eq. 2-3, by
// Simpson on 40000 steps), sampled every 0.01 degree as a table LID (which
// may go negative where the series rings).
Lid LegendreSeries(const Lid& lid, int n) {
  constexpr int kSteps = 40000;
  std::vector<double> k(static_cast<size_t>(n) + 1, 0.0);
  const double h = kPi / kSteps;
  for (int s = 0; s <= kSteps; ++s) {
    const double g = s * h, x = std::cos(g);
    const double simpson = (s == 0 || s == kSteps) ? 1 : (s % 2 ? 4 : 2);
    const double f = lid.Evaluate(g * 180 / kPi) * std::sin(g) * simpson * h / 3;
    double p_prev = 1, p = x;
    for (int l = 0; l <= n; ++l) {
      double pl = l == 0 ? 1 : x;
      if (l >= 2) {
        pl = ((2 * l - 1) * x * p - (l - 1) * p_prev) / l;  // Bonnet
        p_prev = p;
        p = pl;
      }
      k[static_cast<size_t>(l)] += (2 * l + 1) / 2.0 * f * pl;
    }
  }
  Lid out;
  out.kind = relight::baker::LidKind::kTable;
  for (int s = 0; s <= 18000; ++s) {
    const double g = s * 0.01, x = std::cos(g * kPi / 180);
    double p_prev = 1, p = x, v = k[0] + (n >= 1 ? k[1] * x : 0);
    for (int l = 2; l <= n; ++l) {
      const double pl = ((2 * l - 1) * x * p - (l - 1) * p_prev) / l;
      p_prev = p;
      p = pl;
      v += k[static_cast<size_t>(l)] * pl;
    }
    out.gamma_deg.push_back(g);
    out.candela.push_back(v);
  }
  return out;
}

struct Split {
  Eigen::VectorXd first, later;  // per grid point, lux (green)
  Eigen::VectorXd second;        // the part of `later` that reflected exactly twice (dense solver only)
};

Split SplitIndirect(const relight::baker::BakerCore& core, const Eigen::VectorXd& e) {
  constexpr int kGreen = 1;
  const std::array<Eigen::MatrixXd, 3> m = relight::baker::SolveExitanceRgb(core, e);
  const Eigen::VectorXd& rho = relight::baker::Reflectance(core, kGreen);
  const Eigen::VectorXd rho_e = rho.cwiseProduct(e);
  Split s{core.gather[0] * rho_e, core.gather[0] * (m[kGreen].col(0) - rho_e), {}};
  // M = rho (E + F M): the second reflection's exitance is rho F (rho E).
  if (core.form_factors.size() > 0) s.second = core.gather[0] * rho.cwiseProduct(core.form_factors * rho_e);
  return s;
}

int Run(const std::string& path, double zoom, const std::vector<int>& degrees) {
  using namespace relight::baker;
  Scene scene = LoadScene(path);
  size_t l = 0;
  while (l < scene.luminaires.size() && !scene.luminaires[l].lid.zooms()) ++l;
  if (l == scene.luminaires.size()) throw SceneError(path, 0, "no luminaire with a zoom");
  if (scene.grids.empty()) throw SceneError(path, 0, "no calculation grid");
  BakeOptions options;
  options.direct_mode = DirectModeKind::kExact;
  const auto core = BuildBakerCore(scene, options, nullptr);
  const Luminaire& lum = core->scene.luminaires[l];
  const FixtureFrame frame =
      SettingFrame(lum, FixtureSetting{lum.pan_deg, lum.tilt_deg, lum.dimmer, lum.colour});
  const Lid exact = ZoomedBeamLid(lum.lid, zoom);
  const auto patch_e = [&](const Lid& lid) {
    return PatchIlluminance(core->direct[l], [&](const Vec3& d) { return ExactIntensity(lid, frame, d); });
  };
  const Split ref = SplitIndirect(*core, patch_e(exact));
  const std::vector<DirectGeometry>& points = core->direct[l].grids[0];
  Eigen::VectorXd direct = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(points.size()));
  for (size_t k = 0; k < points.size(); ++k) {
    if (points[k].g_m2 > 0)
      direct(static_cast<Eigen::Index>(k)) = points[k].g_m2 * ExactIntensity(exact, frame, points[k].direction);
  }
  const double peak = (direct + ref.first + ref.later).maxCoeff();
  std::printf("%s, luminaire '%s' alone at %.1f deg, grid '%s' (%zu points): peak %.2f lux (green); exact "
              "first hop up to %.2f lux, later bounces up to %.2f lux\n\n",
              path.c_str(), lum.name.c_str(), zoom, core->scene.grids[0].name.c_str(), points.size(), peak,
              ref.first.maxCoeff(), ref.later.maxCoeff());
  std::printf("| indirect from | first hop max | later max | of which second hop | indirect max (point) | indirect mean |\n");
  std::printf("| --- | ---: | ---: | ---: | ---: | ---: |\n");
  const auto row = [&](const std::string& label, const Split& s) {
    const Eigen::VectorXd total = s.first + s.later - ref.first - ref.later;
    Eigen::Index worst = 0;
    const double max_total = total.cwiseAbs().maxCoeff(&worst);
    const Vec3& p = core->scene.grids[0].points[static_cast<size_t>(worst)];
    const double second =
        s.second.size() > 0 ? 100 * (s.second - ref.second).cwiseAbs().maxCoeff() / peak : std::nan("");
    std::printf("| %s | %.3f%% | %.3f%% | %.3f%% | %.3f%% (%ld: %.3f, %.3f) | %.4f%% |\n", label.c_str(),
                100 * (s.first - ref.first).cwiseAbs().maxCoeff() / peak,
                100 * (s.later - ref.later).cwiseAbs().maxCoeff() / peak, second, 100 * max_total / peak,
                static_cast<long>(worst), p[0], p[1], 100 * total.cwiseAbs().mean() / peak);
  };
  for (int n : degrees) {
    Split s = SplitIndirect(*core, patch_e(LegendreSeries(exact, n)));
    row("degree " + std::to_string(n), s);
    s.first = ref.first;
    row("exact hop + degree " + std::to_string(n), s);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"relight-zoom-split: a zooming beam's grid error split into first hop and later bounces,\n"
               "its Legendre series of several degrees against the exact beam (float64, no engine)."};
  std::string scene_path;
  double zoom = 0;
  std::vector<int> degrees{16, 20, 24};
  app.add_option("scene", scene_path, "scene file (.toml) with a zooming luminaire and a grid")->required();
  app.add_option("--zoom", zoom, "beam angle, degrees")->required()->check(CLI::Range(0.5, 179.0));
  app.add_option("--degrees", degrees, "series degrees")->delimiter(',')->check(CLI::Range(0, 64))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  try {
    return Run(scene_path, zoom, degrees);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "relight-zoom-split: error: %s\n", e.what());
    return 2;
  }
}
