// TEMPORARY analysis (issue 12): where the narrow-zoom grid error comes from,
// float64 only. For a zoom angle, compares per grid point:
//  first hop  = gather * (rho E)          (light reflected once)
//  later      = gather * (M - rho E)      (bounced twice or more)
// with E from the exact beam vs from its degree-N Legendre truncation.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "baker_core.h"
#include "reference.h"
#include "relight/baker/beam_profile.h"
#include "relight/baker/lid_error.h"
#include "relight/baker/scene.h"

using namespace relight::baker;

namespace {
constexpr double kPi = 3.14159265358979323846;

// Legendre series of an axisymmetric LID, degree n, sampled as a table.
Lid Truncated(const Lid& lid, int n) {
  const int steps = 40000;
  std::vector<double> k(n + 1, 0.0);
  const double h = kPi / steps;
  for (int s = 0; s <= steps; ++s) {
    const double g = s * h;
    const double w = (s == 0 || s == steps) ? 1 : (s % 2 ? 4 : 2);
    const double x = std::cos(g);
    const double i = lid.Evaluate(g * 180 / kPi) * std::sin(g) * w * h / 3;
    double p0 = 1, p1 = x;
    for (int l = 0; l <= n; ++l) {
      const double p = l == 0 ? 1 : (l == 1 ? x : 0);
      double pl = p;
      if (l >= 2) {
        pl = ((2 * l - 1) * x * p1 - (l - 1) * p0) / l;
        p0 = p1;
        p1 = pl;
      }
      k[l] += (2 * l + 1) / 2.0 * i * pl;
    }
  }
  Lid out;
  out.kind = LidKind::kTable;
  for (int s = 0; s <= 18000; ++s) {
    const double g = s * 0.01;
    const double x = std::cos(g * kPi / 180);
    double p0 = 1, p1 = x, v = k[0] + (n >= 1 ? k[1] * x : 0);
    for (int l = 2; l <= n; ++l) {
      const double pl = ((2 * l - 1) * x * p1 - (l - 1) * p0) / l;
      p0 = p1;
      p1 = pl;
      v += k[l] * pl;
    }
    out.gamma_deg.push_back(g);
    out.candela.push_back(v);
  }
  return out;
}

struct Parts {
  Eigen::VectorXd first, later;  // per grid point, green channel
};

Parts Split(const BakerCore& core, const Eigen::VectorXd& e) {
  const std::array<Eigen::MatrixXd, 3> m = SolveExitanceRgb(core, e);
  const int c = 1;
  const Eigen::VectorXd rho_e = Reflectance(core, c).cwiseProduct(e);
  Parts p;
  p.first = core.gather[0] * rho_e;
  p.later = core.gather[0] * (m[c].col(0) - rho_e);
  return p;
}
}  // namespace

int main(int argc, char** argv) {
  Scene scene = LoadScene(argv[1]);
  const double zoom = std::atof(argv[2]);
  BakeOptions options;
  options.direct_mode = DirectModeKind::kExact;
  options.progress = false;
  ChooseZoomDegrees(&scene, DirectModeKind::kExact);
  auto core = BuildBakerCore(scene, options, nullptr);
  const Luminaire& lum = core->scene.luminaires[0];
  FixtureSetting setting{lum.pan_deg, lum.tilt_deg, lum.dimmer, lum.colour};
  const FixtureFrame frame = SettingFrame(lum, setting);
  const Lid exact = ZoomedBeamLid(lum.lid, zoom);
  const auto patch_e = [&](const Lid& lid) {
    return PatchIlluminance(core->direct[0],
                            [&](const relight::baker::Vec3& d) { return ExactIntensity(lid, frame, d); });
  };
  const Eigen::VectorXd e_exact = patch_e(exact);
  const Parts ref = Split(*core, e_exact);
  // Grid direct and peak of the total (green).
  const auto& gd = core->direct[0].grids[0];
  Eigen::VectorXd direct(static_cast<Eigen::Index>(gd.size()));
  for (size_t k = 0; k < gd.size(); ++k)
    direct(k) = gd[k].g_m2 > 0 ? gd[k].g_m2 * ExactIntensity(exact, frame, gd[k].direction) : 0;
  const Eigen::VectorXd total = direct + ref.first + ref.later;
  const double peak = total.maxCoeff();
  std::printf("zoom %.1f: grid peak %.2f lux (green); first hop max %.2f, later max %.2f lux\n", zoom,
              peak, ref.first.maxCoeff(), ref.later.maxCoeff());
  const auto report = [&](const char* label, const Parts& p) {
    Eigen::Index kf, kl, kt;
    const double ef = (p.first - ref.first).cwiseAbs().maxCoeff(&kf) / peak;
    const double el = (p.later - ref.later).cwiseAbs().maxCoeff(&kl) / peak;
    const double et = (p.first + p.later - ref.first - ref.later).cwiseAbs().maxCoeff(&kt) / peak;
    const double mt = (p.first + p.later - ref.first - ref.later).cwiseAbs().mean() / peak;
    const auto& pt = core->scene.grids[0].points;
    std::printf("  %-28s first hop max %.3f%% (pt %ld)  later max %.3f%% (pt %ld)  indirect max %.3f%% "
                "(pt %ld at %.3f,%.3f) mean %.4f%%\n",
                label, 100 * ef, static_cast<long>(kf), 100 * el, static_cast<long>(kl), 100 * et,
                static_cast<long>(kt), pt[kt][0], pt[kt][1], 100 * mt);
  };
  for (int n : {16, 20, 24, 28, 32}) {
    const Lid sh = Truncated(exact, n);
    char label[64];
    std::snprintf(label, sizeof label, "SH degree %d", n);
    report(label, Split(*core, patch_e(sh)));
    // Route b: exact first hop, SH later bounces.
    Parts b = Split(*core, patch_e(sh));
    b.first = ref.first;
    std::snprintf(label, sizeof label, "exact hop + SH %d later", n);
    report(label, b);
  }
  // Route b2: patch E from the exact vertex direct (area mean of corners).
  {
    const auto& mesh = core->mesh;
    Eigen::VectorXd ev(static_cast<Eigen::Index>(mesh.patch_count()));
    for (size_t i = 0; i < mesh.patch_count(); ++i) {
      const auto& p = mesh.patches[i];
      double s = 0;
      for (int q = 0; q < p.corner_count; ++q) {
        const auto& d = core->direct[0].vertices[p.vertices[q]];
        s += d.g_m2 > 0 ? d.g_m2 * ExactIntensity(exact, frame, d.direction) : 0;
      }
      ev(i) = s / p.corner_count;
    }
    Parts b2 = Split(*core, patch_e(Truncated(exact, 16)));
    b2.first = core->gather[0] * Reflectance(*core, 1).cwiseProduct(ev);
    report("vertex-mean hop + SH 16", b2);
  }
  for (size_t k = 0; k < gd.size(); ++k) {
    if (k % 10 == 0) std::printf("\n");
    std::printf(" %6.1f/%5.1f", direct(k), ref.first(k) + ref.later(k));
  }
  std::printf("\n");
  return 0;
}
