#include "luminaire_basis.h"

#include <algorithm>
#include <vector>

#include "parallel_for.h"
#include "relight/baker/photometry.h"
#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Rows: receivers; columns: G * Y_t(direction) for every term (Dobashi Eq. 15).
Eigen::MatrixXd PointTerms(const std::vector<DirectGeometry>& points, int degree) {
  const int terms = ShTermCount(degree);
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(points.size()), terms);
  std::vector<double> y(static_cast<size_t>(terms));
  for (size_t k = 0; k < points.size(); ++k) {
    if (points[k].g_m2 <= 0) continue;
    EvalShBasis(degree, points[k].direction, y.data());
    for (int t = 0; t < terms; ++t) out(static_cast<Eigen::Index>(k), t) = points[k].g_m2 * y[t];
  }
  return out;
}

// E^(t)_i = sum over patch i's samples of G_s Y_t(direction_s) (Dobashi Eq. 15).
Eigen::MatrixXd PatchTerms(const LuminaireDirect& direct, int degree) {
  const int terms = ShTermCount(degree);
  const Eigen::Index n = static_cast<Eigen::Index>(direct.patch_offsets.size()) - 1;
  Eigen::MatrixXd e = Eigen::MatrixXd::Zero(n, terms);
  std::vector<double> y(static_cast<size_t>(terms));
  for (Eigen::Index i = 0; i < n; ++i) {
    for (uint32_t s = direct.patch_offsets[i]; s < direct.patch_offsets[i + 1]; ++s) {
      const DirectSample& d = direct.patch_samples[s];
      EvalShBasis(degree, d.direction, y.data());
      for (int t = 0; t < terms; ++t) e(i, t) += d.g_m2 * y[t];
    }
  }
  return e;
}

}  // namespace

DirectModeKind EffectiveDirectMode(const BakerCore& core) {
  return core.options.direct_mode.value_or(DirectModeKind::kExact);
}

LuminaireBasis ComputeLuminaireBasis(const BakerCore& core, size_t luminaire, DirectModeKind mode) {
  const Luminaire& lum = core.scene.luminaires[luminaire];
  const LuminaireDirect& direct = core.direct[luminaire];
  const bool exact = mode == DirectModeKind::kExact;
  LuminaireBasis out;
  out.degree = lum.sh_degree;
  out.mode = mode;
  out.sets.resize(1 + core.scene.grids.size());

  // All (N+1)^2 terms as right-hand sides of one factorised system (Eq. 17).
  const Eigen::MatrixXd e = PatchTerms(direct, lum.sh_degree);
  const std::array<Eigen::MatrixXd, 3> m = SolveExitanceRgb(core, e);

  ReceiverBasis& vertices = out.sets[0];
  for (int c = 0; c < 3; ++c) {
    const Eigen::MatrixXd luminance =
        exact ? Eigen::MatrixXd((m[c] - Reflectance(core, c).asDiagonal() * e) / kPi)
              : Eigen::MatrixXd(m[c] / kPi);
    vertices.basis[c] = AverageToVertices(core.mesh, luminance, core.options.threads);
  }
  if (exact) vertices.direct = direct.vertices;

  for (size_t g = 0; g < core.scene.grids.size(); ++g) {
    ReceiverBasis& grid = out.sets[g + 1];
    const Eigen::MatrixXd direct_terms =
        exact ? Eigen::MatrixXd() : PointTerms(direct.grids[g], lum.sh_degree);
    for (int c = 0; c < 3; ++c) {
      grid.basis[c] = core.gather[g] * m[c];
      if (!exact) grid.basis[c] += direct_terms;
    }
    if (exact) grid.direct = direct.grids[g];
  }
  return out;
}

}  // namespace relight::baker
