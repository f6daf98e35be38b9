// What the bake and the reference share, built once per Baker: the mesh,
// the Embree scene, the form factors (patches and grid points), the
// factorised radiosity system and each luminaire's direct geometry.
#pragma once

#include <Eigen/Dense>
#include <memory>
#include <vector>

#include "direct_light.h"
#include "form_factors.h"
#include "hierarchy_solve.h"
#include "mesher.h"
#include "progress.h"
#include "radiosity_solve.h"
#include "relight/baker/baker.h"
#include "visibility.h"

namespace relight::baker {

struct BakerCore {
  Scene scene;
  BakeOptions options;
  Mesh mesh;
  std::unique_ptr<Visibility> visibility;
  PatchSampleSets samples;
  SolverKind solver_kind = SolverKind::kDense;  // the one in use, never kAuto
  Eigen::MatrixXd form_factors;         // dense only: patches x patches
  std::vector<Eigen::MatrixXd> gather;  // per grid: points x patches
  std::unique_ptr<RadiositySolver> solver;                 // dense only
  std::unique_ptr<HierarchicalSolver> hierarchical_solver;  // hierarchical only
  std::vector<LuminaireDirect> direct;  // per luminaire
  BakeReport report;
};

// Exitance M (lm/m^2) per patch and channel from direct illuminance E (lux),
// one column per right-hand side, by whichever solver the core built.
std::array<Eigen::MatrixXd, 3> SolveExitanceRgb(const BakerCore& core,
                                                const Eigen::MatrixXd& illuminance_lux);
// Per patch reflectance of a channel.
const Eigen::VectorXd& Reflectance(const BakerCore& core, int channel);

// Validates what the radiosity stages rely on and builds everything; throws
// SceneError for bad input. `progress` may be null.
std::unique_ptr<BakerCore> BuildBakerCore(const Scene& scene, const BakeOptions& options,
                                          Progress* progress);

// Direct illuminance E_i (lux) per patch for an intensity I(direction) in cd.
template <typename Intensity>
Eigen::VectorXd PatchIlluminance(const LuminaireDirect& direct, Intensity intensity_cd) {
  const Eigen::Index n = static_cast<Eigen::Index>(direct.patch_offsets.size()) - 1;
  Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    for (uint32_t s = direct.patch_offsets[i]; s < direct.patch_offsets[i + 1]; ++s) {
      e(i) += direct.patch_samples[s].g_m2 * intensity_cd(direct.patch_samples[s].direction);
    }
  }
  return e;
}

// Area-weighted average over the patches around each vertex: rows of
// `per_patch` (patches x k) to rows of the result (vertices x k); columns
// on `threads` (as ParallelFor takes them).
Eigen::MatrixXd AverageToVertices(const Mesh& mesh, const Eigen::MatrixXd& per_patch,
                                  int threads = 1);

}  // namespace relight::baker
