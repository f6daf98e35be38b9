#include "direct_light.h"

#include <algorithm>
#include <cmath>

#include "parallel_for.h"
#include "radiosity_vec.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;

// Sample grid per patch edge: 1/d^2 varies fast on patches near the
// luminaire, so those get more points (8 x 8 within one patch diameter).
int DirectSampleGrid(const Patch& p, const Vec3& luminaire_m) {
  const double d = Length(p.centre - luminaire_m);
  if (d < p.diameter_m) return 8;
  if (d < 3.0 * p.diameter_m) return 4;
  return 2;
}

// A vertex moved off its surface and a little into the surface's interior,
// so a ray ending there does not graze the neighbouring surface along an edge.
Vec3 VertexVisibilityPoint(const Mesh& mesh, const Visibility& vis, size_t v) {
  const Vec3& x = mesh.positions[v];
  const Vec3 inward = Normalized(mesh.surface_centroids[mesh.vertex_surface[v]] - x);
  return vis.Offset(x, mesh.vertex_normals[v]) + vis.epsilon_m() * inward;
}

// Solid angle (sr) of a patch seen from point o (Van Oosterom & Strackee,
// summed over a triangle fan; the patch is convex and planar).
double PatchSolidAngle(const Mesh& mesh, const Patch& p, const Vec3& o) {
  double omega = 0;
  const Vec3 a = mesh.positions[p.vertices[0]] - o;
  for (int k = 1; k + 1 < p.corner_count; ++k) {
    const Vec3 b = mesh.positions[p.vertices[k]] - o;
    const Vec3 c = mesh.positions[p.vertices[k + 1]] - o;
    const double la = Length(a), lb = Length(b), lc = Length(c);
    const double num = std::abs(Dot(a, Cross(b, c)));
    const double den = la * lb * lc + Dot(a, b) * lc + Dot(a, c) * lb + Dot(b, c) * la;
    omega += 2.0 * std::atan2(num, den);
  }
  return omega;
}

}  // namespace

DirectGeometry PointDirect(const Visibility& vis, const Vec3& luminaire_m, const Vec3& x,
                           const Vec3& n, const Vec3& x_vis) {
  DirectGeometry out;
  const Vec3 d = x - luminaire_m;
  const double d2 = Dot(d, d);
  if (d2 <= 0) return out;
  out.direction = (1.0 / std::sqrt(d2)) * d;
  const double cos_r = -Dot(out.direction, n);
  if (cos_r <= 0) return out;  // the receiver faces away
  if (!vis.Visible(luminaire_m, x_vis)) return out;
  out.g_m2 = cos_r / d2;
  return out;
}

LuminaireDirect ComputeLuminaireDirect(const Mesh& mesh, const Visibility& vis,
                                       const std::vector<CalcGrid>& grids,
                                       const Vec3& luminaire_m, int threads) {
  LuminaireDirect out;
  const size_t n = mesh.patch_count();
  std::vector<std::vector<DirectSample>> per_patch(n);
  ParallelFor(n, threads, [&](size_t i, int) {
    const Patch& p = mesh.patches[i];
    double unoccluded_sum = 0;
    for (const PatchSample& s : SamplePatch(mesh, p, DirectSampleGrid(p, luminaire_m))) {
      const Vec3 d = s.point - luminaire_m;
      const double d2 = Dot(d, d);
      const double cos_r = d2 > 0 ? -Dot(d, p.normal) / std::sqrt(d2) : 0;
      if (cos_r <= 0) continue;
      unoccluded_sum += s.weight * cos_r / d2;
      DirectSample sample = PointDirect(vis, luminaire_m, s.point, p.normal, vis.Offset(s.point, p.normal));
      if (sample.g_m2 <= 0) continue;
      sample.g_m2 *= s.weight;
      per_patch[i].push_back(sample);
    }
    // The mean of cos / d^2 over a patch is its solid angle over its area
    // (d omega = cos dA / d^2): rescale the samples to that exact mean, so a
    // patch right next to the luminaire gets the right flux, and the samples
    // only distribute it over directions (and visibility).
    if (unoccluded_sum > 0) {
      const double exact = PatchSolidAngle(mesh, p, luminaire_m) / p.area_m2;
      for (DirectSample& sample : per_patch[i]) sample.g_m2 *= exact / unoccluded_sum;
    }
  });
  out.patch_offsets.assign(n + 1, 0);
  for (size_t i = 0; i < n; ++i) {
    out.patch_offsets[i + 1] = out.patch_offsets[i] + static_cast<uint32_t>(per_patch[i].size());
    out.patch_samples.insert(out.patch_samples.end(), per_patch[i].begin(), per_patch[i].end());
  }

  out.vertices.resize(mesh.vertex_count());
  ParallelFor(mesh.vertex_count(), threads, [&](size_t v, int) {
    out.vertices[v] = PointDirect(vis, luminaire_m, mesh.positions[v], mesh.vertex_normals[v],
                                  VertexVisibilityPoint(mesh, vis, v));
  });

  for (const CalcGrid& grid : grids) {
    std::vector<DirectGeometry> g(grid.points.size());
    ParallelFor(grid.points.size(), threads, [&](size_t k, int) {
      g[k] = PointDirect(vis, luminaire_m, grid.points[k], grid.normals[k],
                         vis.Offset(grid.points[k], grid.normals[k]));
    });
    out.grids.push_back(std::move(g));
  }
  return out;
}

}  // namespace relight::baker
