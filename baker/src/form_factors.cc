#include "form_factors.h"

#include <algorithm>
#include <cmath>

#include "contour_integral.h"
#include "parallel_for.h"
#include "polygon_factor_kernel.h"
#include "radiosity_vec.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;

constexpr int kMaxClipped = 8;  // a convex polygon of <= 4 corners clipped by one plane
constexpr size_t kMaxSamples = 32;  // points of a patch's sample set (4 x 4 at most)

// Sutherland-Hodgman against the plane n . (y - x) >= 0. Returns the count.
int ClipToFront(const Vec3& x, const Vec3& n, const Vec3* poly, int count, Vec3* out) {
  int k_out = 0;
  for (int k = 0; k < count; ++k) {
    const Vec3& a = poly[k];
    const Vec3& b = poly[(k + 1) % count];
    const double sa = Dot(n, a - x);
    const double sb = Dot(n, b - x);
    if (sa >= 0) out[k_out++] = a;
    if ((sa >= 0) != (sb >= 0)) out[k_out++] = a + (sa / (sa - sb)) * (b - a);
  }
  return k_out;
}

void PatchCorners(const Mesh& mesh, const Patch& p, Vec3* out) {
  for (int k = 0; k < p.corner_count; ++k) out[k] = mesh.positions[p.vertices[k]];
}

// Signed distance of a point in front of a patch's plane.
double Height(const Patch& p, const Vec3& y) { return Dot(p.normal, y - p.centre); }

// Stratum s of one patch is paired with stratum Pair(s) of the other: a
// fixed permutation, so every stratum on each side shoots exactly one ray.
size_t Pair(size_t s, size_t count) { return (s * (count == 16 ? 7 : 3) + 1) % count; }

// Fraction of unoccluded rays between stratified points of patch a (samples
// sa) and patch b (samples sb). Pairs with an end point behind the other
// patch's plane carry no energy and are skipped.
double VisibleFraction(const Visibility& vis, const Patch& a, const std::vector<PatchSample>& sa,
                       const Patch& b, const std::vector<PatchSample>& sb) {
  int valid = 0;
  VisibleCounter counter(vis);
  for (size_t s = 0; s < sa.size(); ++s) {
    const Vec3& x = sa[s].point;
    const Vec3& y = sb[Pair(s, sb.size())].point;
    if (Height(b, x) <= 0 || Height(a, y) <= 0) continue;
    ++valid;
    counter.Add(vis.Offset(x, a.normal), vis.Offset(y, b.normal));
  }
  const int visible = counter.visible();
  // A sliver with no valid pair: the factor is tiny; keep it unoccluded.
  return valid == 0 ? 1.0 : static_cast<double>(visible) / valid;
}

double PatchToPatchUnoccluded(const Mesh& mesh, const Patch& from,
                              const std::vector<PatchSample>& from_samples, const Patch& to) {
  Vec3 corners[4];
  PatchCorners(mesh, to, corners);
  double point_factor[kMaxSamples];
  const size_t count = std::min(from_samples.size(), kMaxSamples);
  PointsToPolygonFormFactors(from_samples.data(), count, from.normal, corners, to.corner_count, to.normal,
                             point_factor);
  double f = 0;
  for (size_t k = 0; k < count; ++k) f += from_samples[k].weight * point_factor[k];
  return f;
}

// True when no point of `b` lies strictly in front of `a`'s plane: then
// neither patch sees the other (coplanar neighbours, back to back, ...).
bool Behind(const Mesh& mesh, const Patch& a, const Patch& b) {
  const double tol = 1e-9 * a.diameter_m;
  for (int k = 0; k < b.corner_count; ++k)
    if (Height(a, mesh.positions[b.vertices[k]]) > tol) return false;
  return true;
}

}  // namespace

double PointToPolygonFormFactor(const Vec3& x, const Vec3& n, const Vec3* poly, int count,
                                const Vec3& poly_normal) {
  // x on or behind the polygon's plane sees its back (or its edge): no light.
  double size = 0;
  for (int k = 1; k < count; ++k) size = std::max(size, Length(poly[k] - poly[0]));
  if (Dot(poly_normal, x - poly[0]) <= 1e-9 * size) return 0;
  Vec3 clipped[kMaxClipped];
  const int m = ClipToFront(x, n, poly, count, clipped);
  if (m < 3) return 0;
  // Lambert: F = 1/(2 pi) sum_k angle(r_k, r_k+1) n . unit(r_k x r_k+1).
  // The sum's sign follows the polygon's winding as seen from x; after the
  // clip the true value is non-negative, so the magnitude is the factor.
  // Edge terms as polygon_factor_kernel.cc sums them, for the same bits.
  double sum = 0;
  for (int k = 0; k < m; ++k) {
    const Vec3 r0 = clipped[k] - x;
    const Vec3 r1 = clipped[k + 1 == m ? 0 : k + 1] - x;
    sum += ContourEdgeTerm(r0[0], r0[1], r0[2], r1[0], r1[1], r1[2], n[0], n[1], n[2]);
  }
  return FactorFromContourSum(sum);
}

PatchSampleSets BuildPatchSampleSets(const Mesh& mesh) {
  PatchSampleSets sets;
  sets.coarse.reserve(mesh.patch_count());
  sets.fine.reserve(mesh.patch_count());
  for (const Patch& p : mesh.patches) {
    sets.coarse.push_back(SamplePatch(mesh, p, 2));
    sets.fine.push_back(SamplePatch(mesh, p, 4));
  }
  return sets;
}

bool IsNearPair(const Patch& a, const Patch& b) {
  return Length(a.centre - b.centre) < 2.0 * std::max(a.diameter_m, b.diameter_m);
}

bool PatchPairFormFactors(const Mesh& mesh, const Visibility& vis, const PatchSampleSets& samples,
                          size_t i, size_t j, double* f_ij, double* f_ji) {
  *f_ij = *f_ji = 0;
  const Patch& pi = mesh.patches[i];
  const Patch& pj = mesh.patches[j];
  if (Behind(mesh, pi, pj) || Behind(mesh, pj, pi)) return false;
  const bool near = IsNearPair(pi, pj);
  const auto& si = near ? samples.fine[i] : samples.coarse[i];
  const auto& sj = near ? samples.fine[j] : samples.coarse[j];
  const double fij = PatchToPatchUnoccluded(mesh, pi, si, pj);
  const double fji = PatchToPatchUnoccluded(mesh, pj, sj, pi);
  if (fij <= 0 && fji <= 0) return false;
  const double v = VisibleFraction(vis, pi, si, pj, sj);
  *f_ij = fij * v;
  *f_ji = fji * v;
  return true;
}

Eigen::MatrixXd ComputeFormFactors(const Mesh& mesh, const Visibility& vis,
                                   const PatchSampleSets& samples, int threads,
                                   Progress* progress) {
  const size_t n = mesh.patch_count();
  Eigen::MatrixXd f =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(n));
  if (progress) progress->Begin("form factors", n * (n - 1) / 2);
  // Each unordered pair once: both directions share the visibility rays,
  // and each pair writes only its own two entries, so rows need no locks.
  ParallelFor(n, threads, [&](size_t i, int) {
    for (size_t j = i + 1; j < n; ++j) {
      double fij, fji;
      if (!PatchPairFormFactors(mesh, vis, samples, i, j, &fij, &fji)) continue;
      const auto ei = static_cast<Eigen::Index>(i);
      const auto ej = static_cast<Eigen::Index>(j);
      f(ei, ej) = fij;
      f(ej, ei) = fji;
    }
    if (progress) progress->Advance(n - 1 - i);
  });
  if (progress) progress->End();
  return f;
}

Eigen::MatrixXd ComputeGatherFactors(const Mesh& mesh, const Visibility& vis,
                                     const PatchSampleSets& samples,
                                     const std::vector<Vec3>& points,
                                     const std::vector<Vec3>& normals, int threads,
                                     Progress* progress) {
  const size_t n = mesh.patch_count();
  Eigen::MatrixXd g =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(points.size()), static_cast<Eigen::Index>(n));
  if (progress) progress->Begin("grid gather", points.size());
  ParallelFor(points.size(), threads, [&](size_t p, int) {
    const Vec3& x = points[p];
    const Vec3& nx = normals[p];
    const Vec3 origin = vis.Offset(x, nx);
    for (size_t j = 0; j < n; ++j) {
      const Patch& pj = mesh.patches[j];
      Vec3 corners[4];
      PatchCorners(mesh, pj, corners);
      const double ff = PointToPolygonFormFactor(x, nx, corners, pj.corner_count, pj.normal);
      if (ff <= 0) continue;
      const bool near = Length(x - pj.centre) < 2.0 * pj.diameter_m;
      const auto& sj = near ? samples.fine[j] : samples.coarse[j];
      int valid = 0;
      VisibleCounter counter(vis);
      for (const PatchSample& s : sj) {
        if (Dot(nx, s.point - x) <= 0) continue;
        ++valid;
        counter.Add(origin, vis.Offset(s.point, pj.normal));
      }
      const int visible = counter.visible();
      const double v = valid == 0 ? 1.0 : static_cast<double>(visible) / valid;
      g(static_cast<Eigen::Index>(p), static_cast<Eigen::Index>(j)) = ff * v;
    }
    if (progress) progress->Advance();
  });
  if (progress) progress->End();
  return g;
}

}  // namespace relight::baker
