#include "link_brightness.h"

#include <algorithm>
#include <cmath>

namespace relight::baker {
namespace {

// Largest intensity of a distribution (cd), sampled every 0.25 degrees.
double PeakIntensity(const Lid& lid) {
  double peak = 0;
  for (int k = 0; k <= 720; ++k) peak = std::max(peak, lid.Evaluate(0.25 * k));
  return peak;
}

// Area means over each node's leaves of the leaves' values (set in b).
void PullUp(const Hierarchy& h, std::vector<double>* b) {
  // Children follow their parents: in reverse, every child is final first.
  for (size_t k = h.nodes.size(); k-- > 0;) {
    const HierarchyNode& node = h.nodes[k];
    if (node.leaf()) continue;
    double sum = 0;
    for (uint32_t c = node.first_child; c < node.first_child + node.child_count; ++c)
      sum += h.nodes[c].area_m2 * (*b)[c];
    (*b)[k] = sum / node.area_m2;
  }
}

}  // namespace

std::vector<double> PeakDirectIlluminance(const Mesh& mesh, const Scene& scene,
                                          const std::vector<LuminaireDirect>& direct) {
  const size_t n = mesh.patch_count();
  std::vector<double> e(n, 0.0);
  for (size_t l = 0; l < direct.size(); ++l) {
    const double peak = PeakIntensity(scene.luminaires[l].lid);
    const LuminaireDirect& d = direct[l];
    for (size_t i = 0; i < n; ++i) {
      for (uint32_t s = d.patch_offsets[i]; s < d.patch_offsets[i + 1]; ++s)
        e[i] += peak * d.patch_samples[s].g_m2;
    }
  }
  return e;
}

std::vector<double> RefinementBrightness(const Scene& scene, const Mesh& mesh, const Hierarchy& h,
                                         const std::vector<LuminaireDirect>& direct) {
  const size_t n = mesh.patch_count();
  const std::vector<double> e = PeakDirectIlluminance(mesh, scene, direct);
  double flux = 0, area = 0, rho_area = 0;
  for (size_t i = 0; i < n; ++i) {
    const Patch& p = mesh.patches[i];
    flux += e[i] * p.area_m2;
    area += p.area_m2;
    rho_area += p.area_m2 * std::max({p.reflectance[0], p.reflectance[1], p.reflectance[2]});
  }
  const double rho_mean = area > 0 ? rho_area / area : 0;
  const double ambient = area > 0 ? rho_mean * flux / ((1 - rho_mean) * area) : 0;

  std::vector<double> b(h.nodes.size(), 0.0);
  if (!(flux > 0)) {
    std::fill(b.begin(), b.end(), 1.0);
    return b;
  }
  for (size_t k = 0; k < h.nodes.size(); ++k) {
    const HierarchyNode& node = h.nodes[k];
    if (!node.leaf()) continue;
    const Rgb& r = mesh.patches[node.patch].reflectance;
    b[k] = std::max({r[0], r[1], r[2]}) * (e[node.patch] + ambient);
  }
  PullUp(h, &b);
  return b;
}

RefinementEstimate ReceiverRelativeEstimate(const Mesh& mesh, const Hierarchy& h,
                                            const HierarchicalSolver& first,
                                            const std::vector<double>& peak_direct,
                                            double link_epsilon, double absolute_bound) {
  const auto n = static_cast<Eigen::Index>(mesh.patch_count());
  Eigen::MatrixXd e(n, 1);
  for (Eigen::Index i = 0; i < n; ++i) e(i, 0) = peak_direct[static_cast<size_t>(i)];
  const std::array<Eigen::MatrixXd, 3> m = first.SolveExitanceRgb(e);
  const size_t nodes = h.nodes.size();
  std::vector<double> b(nodes, 0.0), least(nodes, 0.0), surface_peak(h.surface_count(), 0.0);
  for (size_t k = 0; k < nodes; ++k) {
    const HierarchyNode& node = h.nodes[k];
    if (!node.leaf()) continue;
    const auto i = static_cast<Eigen::Index>(node.patch);
    double exitance = 0, illuminance = e(i, 0);
    for (int c = 0; c < 3; ++c) {
      const double rho = mesh.patches[node.patch].reflectance[c];
      exitance = std::max(exitance, m[c](i, 0));
      // M = rho (E_direct + E_interreflected): the total illuminance back.
      if (rho > 0) illuminance = std::max(illuminance, m[c](i, 0) / rho);
    }
    b[k] = exitance;
    least[k] = illuminance;
    surface_peak[node.surface] = std::max(surface_peak[node.surface], illuminance);
  }
  PullUp(h, &b);
  for (size_t k = nodes; k-- > 0;) {  // children first
    const HierarchyNode& node = h.nodes[k];
    for (uint32_t c = node.first_child; c < node.first_child + node.child_count; ++c)
      least[k] = c == node.first_child ? least[c] : std::min(least[k], least[c]);
  }
  // Spread: the area mean of |B_leaf - B_node| over each node's leaves.
  std::vector<double> spread(nodes, 0.0);
  for (size_t k = 0; k < nodes; ++k) {
    const HierarchyNode& node = h.nodes[k];
    if (!node.leaf()) continue;
    for (uint32_t a = node.parent; a != kNoNode; a = h.nodes[a].parent)
      spread[a] += node.area_m2 * std::abs(b[k] - b[a]);
  }
  RefinementEstimate out;
  out.brightness.resize(nodes);
  out.bound.resize(nodes);
  for (size_t k = 0; k < nodes; ++k) {
    const HierarchyNode& node = h.nodes[k];
    out.brightness[k] = b[k] + kSourceSpread * spread[k] / node.area_m2;
    const double light = std::max(least[k], kDarkFloor * surface_peak[node.surface]);
    out.bound[k] = std::clamp(kReceiverRelative * link_epsilon * light,
                              kAbsoluteFloor * absolute_bound, absolute_bound);
  }
  return out;
}

}  // namespace relight::baker
