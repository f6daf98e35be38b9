// Chandran & Srivastava's "naive" method, the ground truth run-time emitters
// (FE, AR) are measured against (issue 15): the scene re-solved in float64
// with each emitter as real emission. The emitter polygon is not cut into the
// mesh; each patch it overlaps emits pi L times its exactly covered area
// fraction (float64 clip in the surface's plane), so inside one patch the
// emission is spread evenly: at the finest patch size this is the same as a
// mesh split along the polygon up to the patch's own averaging. Solved by
// the dense solver when the core has one (every patch pair linked), else by
// the core's hierarchical solver (then build the core with a smaller
// link_epsilon than the bake's, so the naive solve refines for the emitter's
// light, as the paper's naive method re-refines).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "baker_core.h"

namespace relight::baker {

struct NaiveEmitter {
  std::string surface;         // an input surface's name
  std::vector<Vec3> corners_m;  // convex, on the surface's plane, 3 or more
  Rgb luminance_cd_m2{};
};

// Covered fraction of every patch (0 off `surface`); throws SceneError for an
// unknown surface or a polygon that is not convex or covers nothing.
Eigen::VectorXd CoveredFraction(const Scene& scene, const Mesh& mesh, const NaiveEmitter& emitter);

// Vertex luminance, cd/m^2 (vertices x 3), with only the emitters lit (the
// scene's luminaires off), by AverageToVertices as the bake's vertex basis.
Eigen::MatrixXd NaiveEmitterVertexLuminance(const BakerCore& core, const std::vector<NaiveEmitter>& emitters);

}  // namespace relight::baker
