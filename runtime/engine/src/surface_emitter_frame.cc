// Surface frames for run-time emitters (surface_emitter_frame.h).
//
// Scaling and overflow: positions Q16.16 (< 2^31), differences < 2^32;
// Newell sums < 2^67 in Int128. Unit vectors: the vector scaled below 2^40,
// its length by ISqrt128, then v * 2^30 / length. Centroids: fan triangles
// weighted by their projected twice-area (< 2^65) times corner sums (< 2^34).
#include "surface_emitter_frame.h"

#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

const int32_t* Corner(const BakeHierarchy& h, const BakeMesh& mesh, uint32_t node, int k) {
  return &mesh.positions[3 * size_t{h.node_corners[size_t{node} * kBakeMaxNodeCorners +
                                                    static_cast<size_t>(k)]}];
}

void UnitQ30(const Int128 v[3], int32_t out[3]) {
  int shift = 0;
  for (int i = 0; i < 3; ++i)
    while ((Abs128(v[i]) >> shift) >= (static_cast<UInt128>(1) << 40)) ++shift;
  Int128 s[3];
  for (int i = 0; i < 3; ++i) s[i] = v[i] >> shift;
  const uint64_t length = ISqrt128(static_cast<UInt128>(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]));
  for (int i = 0; i < 3; ++i) {
    out[i] = length == 0 ? 0
                         : static_cast<int32_t>(RoundShiftSat64(
                               s[i] * (static_cast<Int128>(1) << 30) / static_cast<Int128>(length), 0));
  }
}

}  // namespace

void NodeNormalQ32(const BakeHierarchy& h, const BakeMesh& mesh, uint32_t node, Int128 normal[3]) {
  const int n = h.node_corner_count[node];
  normal[0] = normal[1] = normal[2] = 0;
  for (int k = 0; k < n; ++k) {
    const int32_t* p = Corner(h, mesh, node, k);
    const int32_t* q = Corner(h, mesh, node, (k + 1) % n);
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, l = (i + 2) % 3;
      normal[i] += static_cast<Int128>(int64_t{p[j]} - q[j]) * (int64_t{p[l]} + q[l]);
    }
  }
}

void MakeSurfaceFrameQ30(const BakeHierarchy& h, const BakeMesh& mesh, uint32_t root,
                         SurfaceFrameQ30* frame) {
  Int128 normal[3];
  NodeNormalQ32(h, mesh, root, normal);
  frame->drop_axis = 0;
  for (int i = 1; i < 3; ++i)
    if (Abs128(normal[i]) > Abs128(normal[frame->drop_axis])) frame->drop_axis = i;
  const int32_t* c0 = Corner(h, mesh, root, 0);
  const int32_t* c1 = Corner(h, mesh, root, 1);
  Int128 edge[3];
  for (int i = 0; i < 3; ++i) {
    frame->origin_q16[i] = c0[i];
    edge[i] = int64_t{c1[i]} - c0[i];
  }
  int32_t n_q30[3];
  UnitQ30(normal, n_q30);
  UnitQ30(edge, frame->u_q30);
  const int32_t* u = frame->u_q30;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, l = (i + 2) % 3;
    const Int128 cross = static_cast<Int128>(n_q30[j]) * u[l] - static_cast<Int128>(n_q30[l]) * u[j];
    frame->v_q30[i] = static_cast<int32_t>(RoundShiftSat64(cross, -30));
  }
}

void NodeCentreUvQ16(const BakeHierarchy& h, const BakeMesh& mesh, const SurfaceFrameQ30& frame,
                     uint32_t node, int32_t uv_q16[2]) {
  const int a_axis = (frame.drop_axis + 1) % 3, b_axis = (frame.drop_axis + 2) % 3;
  const int32_t* a = Corner(h, mesh, node, 0);
  Int128 weight = 0, sum[3] = {0, 0, 0};
  for (int k = 1; k + 1 < h.node_corner_count[node]; ++k) {
    const int32_t* b = Corner(h, mesh, node, k);
    const int32_t* c = Corner(h, mesh, node, k + 1);
    const Int128 w = static_cast<Int128>(int64_t{b[a_axis]} - a[a_axis]) * (int64_t{c[b_axis]} - a[b_axis]) -
                     static_cast<Int128>(int64_t{c[a_axis]} - a[a_axis]) * (int64_t{b[b_axis]} - a[b_axis]);
    weight += w;
    // Relative to the origin keeps the sums small.
    for (int i = 0; i < 3; ++i) {
      sum[i] += w * (int64_t{a[i]} + b[i] + c[i] - 3 * int64_t{frame.origin_q16[i]});
    }
  }
  int64_t d[3];
  for (int i = 0; i < 3; ++i) {
    const Int128 den = 3 * weight;
    d[i] = den == 0 ? 0 : static_cast<int64_t>((2 * sum[i] + den) / (2 * den));
  }
  uv_q16[0] = static_cast<int32_t>(RoundShiftSat64(
      static_cast<Int128>(d[0]) * frame.u_q30[0] + static_cast<Int128>(d[1]) * frame.u_q30[1] +
          static_cast<Int128>(d[2]) * frame.u_q30[2], -30));
  uv_q16[1] = static_cast<int32_t>(RoundShiftSat64(
      static_cast<Int128>(d[0]) * frame.v_q30[0] + static_cast<Int128>(d[1]) * frame.v_q30[1] +
          static_cast<Int128>(d[2]) * frame.v_q30[2], -30));
}

}  // namespace relight
