// Direct light of a point luminaire: the geometric factor
//   G = visibility * max(0, cos theta_receiver) / d^2      (m^-2)
// and the direction luminaire -> receiver, so that a luminaire of intensity
// I(direction) candela gives illuminance E = I * G lux (Dobashi Eq. 15's G_i).
// Patches get G over stratified sample points (the solve needs a good mean
// E_i), rescaled so their unoccluded mean is exactly the patch's solid angle
// over its area; vertices and grid points get G at the point itself.
#pragma once

#include <cstdint>
#include <vector>

#include "mesher.h"
#include "visibility.h"

namespace relight::baker {

struct DirectGeometry {
  double g_m2 = 0;   // visibility * cos / d^2
  Vec3 direction{};  // unit, luminaire -> receiver, world frame
};

// One sample point of a patch: its area weight is folded into g_m2, so a
// patch's illuminance is sum over its samples of g_m2 * I(direction).
using DirectSample = DirectGeometry;

struct LuminaireDirect {
  // Samples of patch i: patch_samples[patch_offsets[i] .. patch_offsets[i + 1]),
  // only those that receive light (G > 0).
  std::vector<uint32_t> patch_offsets;
  std::vector<DirectSample> patch_samples;
  std::vector<DirectGeometry> vertices;            // per mesh vertex
  std::vector<std::vector<DirectGeometry>> grids;  // per grid, per point
};

// G and direction at receiver x (unit normal n), the shadow ray ending at
// x_vis (x moved off its surface).
DirectGeometry PointDirect(const Visibility& vis, const Vec3& luminaire_m, const Vec3& x,
                           const Vec3& n, const Vec3& x_vis);

// Every receiver of the scene for a luminaire at `luminaire_m`.
LuminaireDirect ComputeLuminaireDirect(const Mesh& mesh, const Visibility& vis,
                                       const std::vector<CalcGrid>& grids, const Vec3& luminaire_m,
                                       int threads);

}  // namespace relight::baker
