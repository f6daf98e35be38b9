// Form factors between patches, and from calculation-grid points to patches.
//
// The kernel is the analytic differential-area-to-polygon form factor
// (Lambert's contour integral), with the polygon clipped to the half-space
// in front of the receiving point; a polygon seen from its back gives 0.
// Patch-to-patch factors average it over stratified points of the sending
// patch and multiply by the fraction of unoccluded rays between stratified
// points of the two patches (Embree). Near pairs get more points and rays.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "mesher.h"
#include "progress.h"
#include "visibility.h"

namespace relight::baker {

// Form factor from a differential area at x (unit normal n) to the convex
// polygon `poly` (count corners, CCW seen from its front, unit normal
// poly_normal), unoccluded. Dimensionless, in [0, 1].
double PointToPolygonFormFactor(const Vec3& x, const Vec3& n, const Vec3* poly, int count,
                                const Vec3& poly_normal);

// Stratified points per patch, computed once: 2 x 2 for far pairs, 4 x 4 for near ones.
struct PatchSampleSets {
  std::vector<std::vector<PatchSample>> coarse, fine;
};
PatchSampleSets BuildPatchSampleSets(const Mesh& mesh);

// True when patches closer than this (centre distance) need the fine samples.
bool IsNearPair(const Patch& a, const Patch& b);

// F(i, j) and F(j, i) of one patch pair, with visibility: exactly the dense
// matrix's entries (the hierarchical solver's leaf-to-leaf links use it).
// False, with both 0, when the patches cannot see each other.
bool PatchPairFormFactors(const Mesh& mesh, const Visibility& vis, const PatchSampleSets& samples,
                          size_t i, size_t j, double* f_ij, double* f_ji);

// F(i, j): fraction of the light leaving patch i that reaches patch j. Dense
// n x n; rows of a closed, empty enclosure sum to 1. Rows run on `threads`
// (0 = every core).
Eigen::MatrixXd ComputeFormFactors(const Mesh& mesh, const Visibility& vis,
                                   const PatchSampleSets& samples, int threads, Progress* progress);

// G(p, j): form factor from a differential area at point p (unit normal) to
// patch j, with visibility; illuminance at p = sum_j G(p, j) M_j (lux from lm/m^2).
Eigen::MatrixXd ComputeGatherFactors(const Mesh& mesh, const Visibility& vis,
                                     const PatchSampleSets& samples,
                                     const std::vector<Vec3>& points,
                                     const std::vector<Vec3>& normals, int threads,
                                     Progress* progress);

}  // namespace relight::baker
