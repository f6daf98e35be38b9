// How well one solve agrees with another on the same mesh, surface by
// surface: the hierarchical solver's vertex luminances against the dense
// (float64 LU) solve's. A bias shows as a mean signed difference of the same
// sign on every surface; noise as mean |difference| with a signed mean near 0.
// All figures are relative to the surface's own peak (the largest channel
// value over its vertices in `want`), so a dim surface is not hidden by a
// bright one.
#pragma once

#include <string>
#include <vector>

#include "mesher.h"
#include "relight/baker/scene.h"

namespace relight::baker {

struct SurfaceAgreement {
  std::string name;
  double peak = 0;         // of want, cd/m^2
  double mean_signed = 0;  // mean of (got - want) / peak over vertices and channels
  double mean_abs = 0;     // mean of |got - want| / peak
  double max_abs = 0;      // largest |got - want| / peak
};

// got and want: per vertex RGB (mesh.vertex_count() each). One entry per
// input surface, in scene order.
std::vector<SurfaceAgreement> CompareBySurface(const Scene& scene, const Mesh& mesh,
                                               const std::vector<Rgb>& got,
                                               const std::vector<Rgb>& want);

}  // namespace relight::baker
