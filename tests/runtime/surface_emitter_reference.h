// Float64 reference for a run-time emitter that does not depend on the
// hierarchy's links for the emitter's own light: the exact first shot of the
// polygon on every patch (the baker's point-to-polygon kernel at the patch's
// fine quadrature points, visibility by Embree rays to points spread over
// the polygon), interreflected by the baker's own solver (SolveExitanceRgb),
// plus the emitter's own exitance on the patches it covers. Until the naive
// solve (the polygon meshed in as a patch, issue 15 item 3) exists, this is
// what FE and AR are measured against.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <string>
#include <vector>

#include "baker_core.h"
#include "form_factors.h"
#include "hierarchy.h"
#include "radiosity_vec.h"
#include "surface_emitter_test_support.h"

namespace relight::testing {

// Vertex luminance (cd/m^2) per cd/m^2 of the emitter: vertices x 3 channels.
inline Eigen::MatrixXd ReferenceEmitterVertexLuminance(const baker::BakerCore& core,
                                                       const std::string& surface_name,
                                                       const std::vector<Vec3>& polygon) {
  using namespace baker::radiosity_vec;
  const baker::Mesh& mesh = core.mesh;
  uint32_t surface = 0;
  while (core.scene.surfaces[surface].name != surface_name) ++surface;
  Vec3 normal{0, 0, 0};
  for (const baker::Patch& p : mesh.patches)
    if (p.surface == surface) normal = p.normal;
  const std::vector<baker::PatchSample> on_emitter =
      baker::SamplePolygon(polygon.data(), static_cast<int>(polygon.size()), true);
  const AxisPlane plane(normal);
  const std::vector<Vec2> clip = plane.Polygon(polygon);
  const auto n = static_cast<Eigen::Index>(mesh.patch_count());
  Eigen::MatrixXd first_shot = Eigen::MatrixXd::Zero(n, 1);
  Eigen::VectorXd own = Eigen::VectorXd::Zero(n);
  for (size_t i = 0; i < mesh.patch_count(); ++i) {
    const baker::Patch& p = mesh.patches[i];
    if (p.surface == surface) {
      std::vector<Vec3> corners;
      for (int k = 0; k < p.corner_count; ++k) corners.push_back(mesh.positions[p.vertices[k]]);
      const std::vector<Vec2> patch = plane.Polygon(corners);
      const std::vector<Vec2> cut = ClipConvex(patch, clip);
      if (cut.size() >= 3) own(static_cast<Eigen::Index>(i)) = SignedArea(cut) / SignedArea(patch);
      continue;
    }
    double e = 0;
    for (const baker::PatchSample& s : core.samples.fine[i]) {
      const double f = baker::PointToPolygonFormFactor(s.point, p.normal, polygon.data(),
                                                       static_cast<int>(polygon.size()), normal);
      if (f <= 0) continue;
      int valid = 0, visible = 0;
      const Vec3 from = core.visibility->Offset(s.point, p.normal);
      for (const baker::PatchSample& t : on_emitter) {
        if (Dot(p.normal, t.point - s.point) <= 0) continue;
        ++valid;
        if (core.visibility->Visible(from, core.visibility->Offset(t.point, normal))) ++visible;
      }
      e += s.weight * f * (valid == 0 ? 1.0 : static_cast<double>(visible) / valid);
    }
    first_shot(static_cast<Eigen::Index>(i), 0) = e;  // lux per lm/m^2 of the emitter
  }
  const std::array<Eigen::MatrixXd, 3> reflected = baker::SolveExitanceRgb(core, first_shot);
  Eigen::MatrixXd exitance(n, 3);
  for (int c = 0; c < 3; ++c) exitance.col(c) = reflected[static_cast<size_t>(c)].col(0) + own;
  // Unit exitance is pi x 1 cd/m^2, and luminance = exitance / pi: the pi cancels.
  return baker::AverageToVertices(mesh, exitance);
}

}  // namespace relight::testing
