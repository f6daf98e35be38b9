// Node polygons cut by an emitter in 3D (emitter_clip3.h).
//
// Scaling and overflow: Q16.16 metres in int64. A side test is (edge,
// < 2^33) x (point - start, < 2^33) < 2^67 in Int128; a crossing moves a
// corner by (p - s) ds / (ds - dp): < 2^33 x 2^67 in Int128, rounded.
#include "emitter_clip3.h"

#include "relight/base/fixed_ops.h"

namespace relight {

void EmitterClip3::Set(const SurfaceEmitterShape& shape, int drop_axis) {
  a_ = (drop_axis + 1) % 3;
  b_ = (drop_axis + 2) % 3;
  count_ = shape.corner_count;
  Int128 twice_area = 0;
  for (int k = 0; k < count_; ++k) {
    e_[k][0] = shape.corners_q16[k][a_];
    e_[k][1] = shape.corners_q16[k][b_];
  }
  for (int k = 0; k < count_; ++k) {
    const int64_t* p = e_[k];
    const int64_t* q = e_[(k + 1) % count_];
    twice_area += static_cast<Int128>(p[0]) * q[1] - static_cast<Int128>(q[0]) * p[1];
  }
  if (twice_area < 0) {  // make it counter-clockwise: inside is left of every edge
    for (int i = 0, j = count_ - 1; i < j; ++i, --j)
      for (int d = 0; d < 2; ++d) {
        const int64_t t = e_[i][d];
        e_[i][d] = e_[j][d];
        e_[j][d] = t;
      }
  }
}

Int128 EmitterClip3::Side(int k, const int64_t* p) const {
  const int64_t* s = e_[k];
  const int64_t* t = e_[(k + 1) % count_];
  return static_cast<Int128>(t[0] - s[0]) * (p[b_] - s[1]) - static_cast<Int128>(t[1] - s[1]) * (p[a_] - s[0]);
}

int EmitterClip3::Clip(const BakeHierarchy& h, const BakeMesh& mesh, uint32_t node, int64_t (*out)[3]) const {
  int64_t poly[kMaxFactorPolygonCorners][3], next[kMaxFactorPolygonCorners][3];
  int n = h.node_corner_count[node];
  for (int k = 0; k < n; ++k) {
    const int32_t* p = &mesh.positions[3 * size_t{h.node_corners[size_t{node} * kBakeMaxNodeCorners + static_cast<size_t>(k)]}];
    for (int i = 0; i < 3; ++i) poly[k][i] = p[i];
  }
  for (int edge = 0; edge < count_ && n > 0; ++edge) {
    int m = 0;
    for (int k = 0; k < n; ++k) {
      const int64_t* s = poly[(k + n - 1) % n];
      const int64_t* p = poly[k];
      const Int128 ds = Side(edge, s), dp = Side(edge, p);
      // A convex node cut by a convex emitter has at most 6 + 8 corners.
      if ((ds < 0) != (dp < 0) && m < kMaxFactorPolygonCorners) {
        const Int128 den = ds - dp, sign = den < 0 ? -1 : 1;
        for (int i = 0; i < 3; ++i)
          next[m][i] = s[i] + static_cast<int64_t>(DivRound(static_cast<Int128>(p[i] - s[i]) * ds * sign, den * sign));
        ++m;
      }
      if (dp >= 0 && m < kMaxFactorPolygonCorners) {
        for (int i = 0; i < 3; ++i) next[m][i] = p[i];
        ++m;
      }
    }
    for (int k = 0; k < m; ++k)
      for (int i = 0; i < 3; ++i) poly[k][i] = next[k][i];
    n = m;
  }
  if (n < 3) return 0;
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < 3; ++i) out[k][i] = poly[k][i];
  return n;
}

}  // namespace relight
