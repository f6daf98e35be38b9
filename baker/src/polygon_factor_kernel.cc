#include "polygon_factor_kernel.h"

#include <algorithm>

#include "contour_integral.h"
#include "form_factors.h"
#include "radiosity_vec.h"

// GCC builds one copy of the loop per listed x86-64 extension and picks the
// widest the CPU has at load time. Compiled with -O3 -ffp-contract=off
// -fno-math-errno -fno-trapping-math (CMakeLists.txt): the edge terms vectorise over the points,
// without multiply-add contraction, so every copy and the one-point function
// give the same bits.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define RELIGHT_FACTOR_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define RELIGHT_FACTOR_CLONES
#endif

namespace relight::baker {
namespace {

using namespace radiosity_vec;

constexpr size_t kBatch = 32;  // points a pass (the largest sample set)

// sum[i] = the contour sum of the unclipped polygon seen from (x[i], y[i], z[i]).
RELIGHT_FACTOR_CLONES void ContourSums(const double* __restrict x, const double* __restrict y,
                                       const double* __restrict z, size_t n_points, const Vec3& n,
                                       const Vec3* poly, int count, double* __restrict sum) {
  for (size_t i = 0; i < n_points; ++i) sum[i] = 0;
  const double nx = n[0], ny = n[1], nz = n[2];
  for (int k = 0; k < count; ++k) {
    const Vec3& a = poly[k];
    const Vec3& b = poly[k + 1 == count ? 0 : k + 1];
    for (size_t i = 0; i < n_points; ++i) {
      sum[i] += ContourEdgeTerm(a[0] - x[i], a[1] - y[i], a[2] - z[i], b[0] - x[i], b[1] - y[i],
                                b[2] - z[i], nx, ny, nz);
    }
  }
}

}  // namespace

void PointsToPolygonFormFactors(const PatchSample* points, size_t point_count, const Vec3& n,
                                const Vec3* poly, int count, const Vec3& poly_normal, double* out) {
  double size = 0;
  for (int k = 1; k < count; ++k) size = std::max(size, Length(poly[k] - poly[0]));
  double x[kBatch], y[kBatch], z[kBatch], sum[kBatch];
  size_t index[kBatch];
  for (size_t first = 0; first < point_count; first += kBatch) {
    const size_t last = std::min(point_count, first + kBatch);
    size_t lanes = 0;
    for (size_t i = first; i < last; ++i) {
      const Vec3& p = points[i].point;
      out[i] = 0;
      if (Dot(poly_normal, p - poly[0]) <= 1e-9 * size) continue;  // the polygon's back
      bool whole = true;  // every corner in front of p's plane: no clip
      for (int k = 0; k < count && whole; ++k) whole = Dot(n, poly[k] - p) >= 0;
      if (!whole) {
        out[i] = PointToPolygonFormFactor(p, n, poly, count, poly_normal);
        continue;
      }
      x[lanes] = p[0];
      y[lanes] = p[1];
      z[lanes] = p[2];
      index[lanes++] = i;
    }
    if (lanes == 0 || count < 3) continue;
    ContourSums(x, y, z, lanes, n, poly, count, sum);
    for (size_t l = 0; l < lanes; ++l) out[index[l]] = FactorFromContourSum(sum[l]);
  }
}

}  // namespace relight::baker
