// The naive ground truth for run-time emitters (naive_emitter.h).
#include "naive_emitter.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "plane_polygon.h"
#include "radiosity_vec.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;
constexpr double kPi = 3.14159265358979323846;

// The plane seen along its normal's largest axis (area ratios are kept),
// counter-clockwise.
std::vector<Vec2> Project(const std::vector<Vec3>& corners, int drop) {
  const int a = (drop + 1) % 3, b = (drop + 2) % 3;
  std::vector<Vec2> out;
  for (const Vec3& c : corners) out.push_back({c[a], c[b]});
  if (SignedArea(out) < 0) std::reverse(out.begin(), out.end());
  return out;
}

}  // namespace

Eigen::VectorXd CoveredFraction(const Scene& scene, const Mesh& mesh, const NaiveEmitter& emitter) {
  uint32_t surface = 0;
  while (surface < scene.surfaces.size() && scene.surfaces[surface].name != emitter.surface) ++surface;
  if (surface == scene.surfaces.size())
    throw SceneError(scene.path, 0, "naive emitter: no surface '" + emitter.surface + "'");
  const std::vector<Vec3>& sc = scene.surfaces[surface].corners;
  const Vec3 n = Cross(sc[1] - sc[0], sc[2] - sc[0]);
  int drop = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(n[i]) > std::abs(n[drop])) drop = i;
  const std::vector<Vec2> clip = Project(emitter.corners_m, drop);
  for (size_t i = 0; i < clip.size(); ++i) {  // strictly convex, counter-clockwise
    const Vec2 &a = clip[i], &b = clip[(i + 1) % clip.size()], &c = clip[(i + 2) % clip.size()];
    if ((b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]) <= 0)
      throw SceneError(scene.path, scene.surfaces[surface].line,
                       "naive emitter on '" + emitter.surface + "': polygon not strictly convex");
  }
  Eigen::VectorXd fraction = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(mesh.patch_count()));
  for (size_t i = 0; i < mesh.patch_count(); ++i) {
    const Patch& p = mesh.patches[i];
    if (p.surface != surface) continue;
    std::vector<Vec3> corners;
    for (int k = 0; k < p.corner_count; ++k) corners.push_back(mesh.positions[p.vertices[static_cast<size_t>(k)]]);
    const std::vector<Vec2> patch = Project(corners, drop);
    const std::vector<Vec2> cut = ClipConvex(patch, clip);
    if (cut.size() >= 3) fraction(static_cast<Eigen::Index>(i)) = SignedArea(cut) / SignedArea(patch);
  }
  if (fraction.sum() <= 0)
    throw SceneError(scene.path, scene.surfaces[surface].line,
                     "naive emitter on '" + emitter.surface + "' covers no patch");
  return fraction;
}

Eigen::MatrixXd NaiveEmitterVertexLuminance(const BakerCore& core, const std::vector<NaiveEmitter>& emitters) {
  const Eigen::Index patches = static_cast<Eigen::Index>(core.mesh.patch_count());
  Eigen::MatrixXd out(static_cast<Eigen::Index>(core.mesh.vertex_count()), 3);
  std::vector<Eigen::VectorXd> fractions;
  for (const NaiveEmitter& e : emitters) fractions.push_back(CoveredFraction(core.scene, core.mesh, e));
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd emitted = Eigen::VectorXd::Zero(patches);  // M = pi L, lm/m^2
    for (size_t i = 0; i < emitters.size(); ++i) emitted += kPi * emitters[i].luminance_cd_m2[c] * fractions[i];
    const Eigen::MatrixXd exitance = core.solver ? core.solver->Solve(c, emitted)
                                                 : core.hierarchical_solver->Solve(c, emitted);
    out.col(c) = AverageToVertices(core.mesh, exitance).col(0) / kPi;
  }
  return out;
}

}  // namespace relight::baker
