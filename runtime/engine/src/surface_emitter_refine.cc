// Adaptive refine (surface_emitter_refine.h).
//
// Scaling and overflow: positions Q16.16 metres in int64 (the clip:
// emitter_clip3.h). Factors UQ0.32 summed over <= 6 points in uint64. A ratio is UQ0.32 (<= 1: the clipped polygon lies inside
// the node's). f (UQ0.32) x ratio -> Q32 irradiance per unit exitance;
// g (Q8.23 per metre) x ratio (Q32) >> 23 -> Q32 per metre, as the solver's
// gathers (surface_emitter_solve.cc). Coverage means: area (Q32.32 m^2,
// < 2^64) x fraction (<= 2^32) summed over <= 4 children, < 2^98.
#include "surface_emitter_refine.h"

#include <algorithm>

#include "emitter_clip3.h"
#include "point_polygon_factor.h"
#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"
#include "surface_emitter_frame.h"

namespace relight {
namespace {

constexpr int64_t kOne = int64_t{1} << 32;
constexpr int kStackNodes = 1024;
// Receivers further than this many of their radii from the polygon take the
// factor at their centroid only.
constexpr int64_t kFarRadii = 4;
// BF's threshold on F x B for the emitter's light, B its covered fraction
// (UQ0.32): 2^-10 of its exitance. Measured (docs/hierarchy.md, "AR"):
// 2^-11 halves the living room's remaining mean error at 2-3x the new links.
constexpr uint64_t kRefineThresholdQ32 = uint64_t{1} << 22;

const int32_t* CornerQ16(const BakeHierarchy& h, const BakeMesh& mesh, uint32_t node, int k) {
  return &mesh.positions[3 * size_t{h.node_corners[size_t{node} * kBakeMaxNodeCorners + static_cast<size_t>(k)]}];
}

int64_t GradientTerm(int64_t gu, int64_t gv, const int32_t* uv_q16) {
  return RoundShiftSat64(static_cast<Int128>(gu) * uv_q16[0] + static_cast<Int128>(gv) * uv_q16[1], -16);
}

// Unit normal (Q1.30) of a Newell normal of any scale.
void UnitNormal(const Int128 normal[3], int32_t out_q30[3]) {
  UInt128 big = 0;
  for (int i = 0; i < 3; ++i)
    if (Abs128(normal[i]) > big) big = Abs128(normal[i]);
  const int shift = BitLength128(big) > 60 ? BitLength128(big) - 60 : 0;
  const int64_t v[3] = {static_cast<int64_t>(normal[0] >> shift), static_cast<int64_t>(normal[1] >> shift),
                        static_cast<int64_t>(normal[2] >> shift)};
  if (v[0] == 0 && v[1] == 0 && v[2] == 0) {
    out_q30[0] = out_q30[1] = out_q30[2] = 0;
    return;
  }
  NormaliseQ30(v, out_q30);
}

}  // namespace

Status SurfaceEmitterRefine::Open(const Bake& bake, int pool_links) {
  if (!bake.hierarchy) return Status(StatusCode::kUnsupported, "bake has no hierarchy");
  if (pool_links < 0) return Status(StatusCode::kInvalidArgument, "surface emitter: refine pool < 0 links");
  h_ = &*bake.hierarchy;
  mesh_ = &bake.mesh;
  const BakeHierarchy& h = *h_;
  const uint32_t n = h.node_count();
  centroid_q16_.assign(size_t{n} * 3, 0);
  centre_uv_q16_.assign(size_t{n} * 2, 0);
  normal_q30_.assign(bake.mesh.surface_names.size() * 3, 0);
  drop_axis_.assign(bake.mesh.surface_names.size(), 0);
  frame_u_q30_.assign(bake.mesh.surface_names.size() * 3, 0);
  frame_v_q30_.assign(bake.mesh.surface_names.size() * 3, 0);
  tree_end_.assign(n, 0);
  SurfaceFrameQ30 frame{};
  uint32_t root = 0;
  for (uint32_t k = 0; k < n; ++k) {
    if (h.node_parent[k] == kBakeNoIndex) {
      if (k > 0) tree_end_[root] = k;
      root = k;
      MakeSurfaceFrameQ30(h, bake.mesh, k, &frame);
      const size_t s = h.node_surface[k];
      for (int i = 0; i < 3; ++i) {
        frame_u_q30_[3 * s + static_cast<size_t>(i)] = frame.u_q30[i];
        frame_v_q30_[3 * s + static_cast<size_t>(i)] = frame.v_q30[i];
      }
      Int128 normal[3];
      NodeNormalQ32(h, bake.mesh, k, normal);
      UnitNormal(normal, &normal_q30_[3 * s]);
      drop_axis_[s] = static_cast<uint8_t>(frame.drop_axis);
    }
    NodeCentreUvQ16(h, bake.mesh, frame, k, &centre_uv_q16_[2 * size_t{k}]);
    // Area centroid in 3D: fan triangles weighted by their area projected
    // along the surface's axis (proportional to the true areas).
    const int a_axis = (frame.drop_axis + 1) % 3, b_axis = (frame.drop_axis + 2) % 3;
    const int32_t* c0 = CornerQ16(h, bake.mesh, k, 0);
    Int128 weight = 0, sum[3] = {0, 0, 0};
    for (int j = 1; j + 1 < h.node_corner_count[k]; ++j) {
      const int32_t* b = CornerQ16(h, bake.mesh, k, j);
      const int32_t* c = CornerQ16(h, bake.mesh, k, j + 1);
      const Int128 w = static_cast<Int128>(int64_t{b[a_axis]} - c0[a_axis]) * (int64_t{c[b_axis]} - c0[b_axis]) -
                       static_cast<Int128>(int64_t{c[a_axis]} - c0[a_axis]) * (int64_t{b[b_axis]} - c0[b_axis]);
      weight += w;
      for (int i = 0; i < 3; ++i) sum[i] += w * (int64_t{b[i]} + c[i] - 2 * int64_t{c0[i]});
    }
    for (int i = 0; i < 3; ++i)
      centroid_q16_[3 * size_t{k} + i] = c0[i] + (weight == 0 ? 0 : static_cast<int64_t>(DivRound(sum[i], 3 * (weight < 0 ? -weight : weight)) * (weight < 0 ? -1 : 1)));
  }
  if (n > 0) tree_end_[root] = n;
  receiver_radius_q16_.assign(n, 0);
  for (uint32_t k = 0; k < n; ++k) {
    int64_t corners[kBakeMaxNodeCorners][3], centre[3];
    Bound(corners, Corners(k, corners), centre, &receiver_radius_q16_[k]);
  }
  // Per source node, the link sides its light leaves through.
  send_offsets_.assign(size_t{n} + 1, 0);
  for (uint32_t i = 0; i < h.link_count(); ++i) {
    if (h.link_f_pq[i] != 0) ++send_offsets_[h.link_q[i] + 1];
    if (h.link_f_qp[i] != 0) ++send_offsets_[h.link_p[i] + 1];
  }
  for (uint32_t k = 0; k < n; ++k) send_offsets_[k + 1] += send_offsets_[k];
  send_.assign(send_offsets_[n], 0);
  std::vector<uint32_t> fill(send_offsets_.begin(), send_offsets_.end() - 1);
  for (uint32_t i = 0; i < h.link_count(); ++i) {
    if (h.link_f_pq[i] != 0) send_[fill[h.link_q[i]]++] = 2 * i;
    if (h.link_f_qp[i] != 0) send_[fill[h.link_p[i]]++] = 2 * i + 1;
  }
  coverage_mean_q32_.assign(n, 0);
  e0_.assign(n, 0);
  eu_.assign(n, 0);
  ev_.assign(n, 0);
  pool_.assign(static_cast<size_t>(pool_links), NewLink{0, 0, 0, 0});
  refine_threshold_q32_ = kRefineThresholdQ32;
  return Status::Ok();
}

int SurfaceEmitterRefine::Corners(uint32_t node, int64_t (*out)[3]) const {
  const int count = h_->node_corner_count[node];
  for (int k = 0; k < count; ++k)
    for (int i = 0; i < 3; ++i) out[k][i] = CornerQ16(*h_, *mesh_, node, k)[i];
  return count;
}

// The centre of a polygon's corners and their largest distance from it.
void SurfaceEmitterRefine::Bound(const int64_t (*poly)[3], int count, int64_t centre[3], int64_t* radius) {
  for (int i = 0; i < 3; ++i) centre[i] = 0;
  for (int k = 0; k < count; ++k)
    for (int i = 0; i < 3; ++i) centre[i] += poly[k][i];
  for (int i = 0; i < 3; ++i) centre[i] = count == 0 ? 0 : centre[i] / count;
  UInt128 largest = 0;
  for (int k = 0; k < count; ++k) {
    Int128 d2 = 0;
    for (int i = 0; i < 3; ++i) d2 += static_cast<Int128>(poly[k][i] - centre[i]) * (poly[k][i] - centre[i]);
    largest = std::max(largest, static_cast<UInt128>(d2));
  }
  *radius = static_cast<int64_t>(ISqrt128(largest));
}

// True when the receiver's centroid is further from the polygon's nearest
// possible point (its bound) than kFarRadii of the receiver's radius.
// Squares of Q16.16 differences (< 2^33) in Int128.
bool SurfaceEmitterRefine::Far(uint32_t receiver, const int64_t centre[3], int64_t radius) const {
  const int64_t* c = &centroid_q16_[3 * size_t{receiver}];
  Int128 d2 = 0;
  for (int i = 0; i < 3; ++i) d2 += static_cast<Int128>(c[i] - centre[i]) * (c[i] - centre[i]);
  const Int128 reach = static_cast<Int128>(radius) + kFarRadii * receiver_radius_q16_[receiver];
  return d2 > reach * reach;
}

// Sum of F from the receiver's quadrature points to the polygon: half way
// from its centroid to each corner (a quad's 2 x 2 bilinear midpoints when it
// is a parallelogram), so the mean is this over the corner count.
uint64_t SurfaceEmitterRefine::SumFactorsQ32(uint32_t receiver, const int64_t (*poly)[3], int count,
                                             const int64_t centre[3], int64_t radius,
                                             int64_t gradient_q32[2]) const {
  const BakeHierarchy& h = *h_;
  const size_t surface = h.node_surface[receiver];
  const int32_t* n = &normal_q30_[3 * surface];
  const int64_t* c = &centroid_q16_[3 * size_t{receiver}];
  const int corners = h.node_corner_count[receiver];
  if (gradient_q32 == nullptr && Far(receiver, centre, radius)) {
    // Far from the polygon the factor is nearly linear over the receiver:
    // its centroid alone gives the mean (a quarter of the kernel's cost).
    const int64_t x[3] = {c[0], c[1], c[2]};
    return uint64_t{PointToPolygonFactorQ32(x, n, poly, count)} * static_cast<uint64_t>(corners);
  }
  uint64_t sum = 0;
  uint32_t value[kBakeMaxNodeCorners];
  int64_t d[kBakeMaxNodeCorners][2];  // point - centroid along u, v: Q8 metres
  for (int k = 0; k < corners; ++k) {
    const int32_t* corner = CornerQ16(h, *mesh_, receiver, k);
    const int64_t x[3] = {(c[0] + corner[0]) / 2, (c[1] + corner[1]) / 2, (c[2] + corner[2]) / 2};
    value[k] = PointToPolygonFactorQ32(x, n, poly, count);
    sum += value[k];
    if (gradient_q32 == nullptr) continue;
    for (int a = 0; a < 2; ++a) {
      const int32_t* axis = a == 0 ? &frame_u_q30_[3 * surface] : &frame_v_q30_[3 * surface];
      const Int128 dot = static_cast<Int128>(x[0] - c[0]) * axis[0] + static_cast<Int128>(x[1] - c[1]) * axis[1] +
                         static_cast<Int128>(x[2] - c[2]) * axis[2];
      d[k][a] = RoundShiftSat64(dot, -38);  // Q16 x Q30 -> Q8
    }
  }
  if (gradient_q32 == nullptr) return sum;
  // Least squares: G = M^-1 sum_k d_k (v_k - mean), M = sum_k d_k d_k^T.
  // d < 2^23 (Q8, < 32 km), so M < 2^49, det < 2^99; values - mean < 2^33.
  const int64_t mean = static_cast<int64_t>(sum / static_cast<uint64_t>(corners));
  Int128 m00 = 0, m01 = 0, m11 = 0, b0 = 0, b1 = 0;
  for (int k = 0; k < corners; ++k) {
    m00 += static_cast<Int128>(d[k][0]) * d[k][0];
    m01 += static_cast<Int128>(d[k][0]) * d[k][1];
    m11 += static_cast<Int128>(d[k][1]) * d[k][1];
    b0 += static_cast<Int128>(d[k][0]) * (int64_t{value[k]} - mean);
    b1 += static_cast<Int128>(d[k][1]) * (int64_t{value[k]} - mean);
  }
  const Int128 det = m00 * m11 - m01 * m01;
  gradient_q32[0] = gradient_q32[1] = 0;
  if (det <= 0) return sum;
  // adj(M) b < 2^49 x 2^59; / det gives Q32 per Q8 metre, x 2^8 per metre.
  gradient_q32[0] = RoundShiftSat64(DivRound((m11 * b0 - m01 * b1) * 256, det), 0);
  gradient_q32[1] = RoundShiftSat64(DivRound((m00 * b1 - m01 * b0) * 256, det), 0);
  return sum;
}

void SurfaceEmitterRefine::Add(uint32_t receiver, int64_t e0, int64_t eu, int64_t ev) {
  if (needed_ < pool_.size()) pool_[needed_] = {receiver, e0, eu, ev};
  ++needed_;  // past the pool: only counts what the placement would need
}

void SurfaceEmitterRefine::Send(uint32_t link_side, uint64_t ratio_q32) {
  const BakeHierarchy& h = *h_;
  const uint32_t link = link_side >> 1;
  const bool from_p = (link_side & 1) != 0;
  const uint32_t r = from_p ? h.link_q[link] : h.link_p[link];
  const uint32_t f = from_p ? h.link_f_qp[link] : h.link_f_pq[link];
  const int32_t* g = from_p ? &h.link_g_qp[2 * size_t{link}] : &h.link_g_pq[2 * size_t{link}];
  e0_[r] = AddSat64(e0_[r], RoundShiftSat64(static_cast<Int128>(f) * ratio_q32, -32));
  if (g[0] != 0 || g[1] != 0) {
    eu_[r] = AddSat64(eu_[r], RoundShiftSat64(static_cast<Int128>(g[0]) * ratio_q32, -kBakeGradientFracBits));
    ev_[r] = AddSat64(ev_[r], RoundShiftSat64(static_cast<Int128>(g[1]) * ratio_q32, -kBakeGradientFracBits));
  }
}

// Below a receiver the stored link treated as one node: each child gets the
// emitter's light at its own points, with the link's visibility (route (a)).
void SurfaceEmitterRefine::RefineReceiver(uint32_t node, const Source& source, uint64_t visibility_q32,
                                          uint64_t reverse_q32) {
  const BakeHierarchy& h = *h_;
  if (!h.leaf(node) && ((reverse_q32 * source.coverage_q32) >> 32) >= refine_threshold_q32_) {
    const uint32_t first = h.node_first_child[node];
    for (uint32_t c = first; c < first + h.node_child_count[node]; ++c) {
      const uint64_t share = static_cast<uint64_t>((static_cast<UInt128>(reverse_q32) * h.node_area[c]) / h.node_area[node]);
      RefineReceiver(c, source, visibility_q32, share);
    }
    return;
  }
  if (needed_ >= pool_.size()) return Add(node, 0, 0, 0);
  // An inner node left here keeps the light's slope over it, as a stored
  // link's gradient does; a leaf takes its mean.
  int64_t slope[2] = {0, 0};
  const uint64_t sum =
      SumFactorsQ32(node, source.poly, source.count, source.centre, source.radius, h.leaf(node) ? nullptr : slope);
  const uint64_t mean = sum / static_cast<uint64_t>(h.node_corner_count[node]);
  Add(node, RoundShiftSat64(static_cast<Int128>(mean) * visibility_q32, -32),
      RoundShiftSat64(static_cast<Int128>(slope[0]) * visibility_q32, -32),
      RoundShiftSat64(static_cast<Int128>(slope[1]) * visibility_q32, -32));
}

// One link of an emitting node: FE's share where it carries little of the
// emitter's light (BF's F x B below the threshold), else new factors.
void SurfaceEmitterRefine::SendLink(const Source& source, uint32_t link_side) {
  const BakeHierarchy& h = *h_;
  const uint32_t link = link_side >> 1;
  const bool from_p = (link_side & 1) != 0;
  const uint32_t r = from_p ? h.link_q[link] : h.link_p[link];
  const uint64_t f = from_p ? h.link_f_qp[link] : h.link_f_pq[link];
  const uint64_t reverse = from_p ? h.link_f_pq[link] : h.link_f_qp[link];  // r's size seen from the source
  const uint64_t cov = source.coverage_q32;
  // Where in the node the emitter sits matters when the node looks large
  // from the receiver; how the light varies over the receiver, when the
  // receiver looks large from the emitter.
  const bool refine_source = source.partial && ((f * cov) >> 32) >= refine_threshold_q32_;
  const bool refine_receiver = !h.leaf(r) && ((reverse * cov) >> 32) >= refine_threshold_q32_;
  if (!refine_source && !refine_receiver) return Send(link_side, cov);
  if (needed_ >= pool_.size()) {  // over: count, do not compute
    if (!refine_receiver) return Add(r, 0, 0, 0);
    return RefineReceiver(r, source, 0, reverse);
  }
  int64_t whole[kBakeMaxNodeCorners][3], whole_centre[3], whole_radius = 0;
  const int whole_count = Corners(source.node, whole);
  Bound(whole, whole_count, whole_centre, &whole_radius);
  const uint64_t den = SumFactorsQ32(r, whole, whole_count, whole_centre, whole_radius);
  // The receiver sees the node only edge-on at its points: keep FE's share.
  if (den == 0) return Send(link_side, cov);
  // The same points for both, so the ratio is the emitter's share as r sees it.
  const uint64_t num =
      source.partial ? SumFactorsQ32(r, source.poly, source.count, whole_centre, whole_radius) : den;
  if (!refine_receiver) {
    const UInt128 ratio = (static_cast<UInt128>(num) << 32) / den;
    const int32_t* g = from_p ? &h.link_g_qp[2 * size_t{link}] : &h.link_g_pq[2 * size_t{link}];
    const uint64_t ratio_q32 = ratio > (static_cast<UInt128>(1) << 32) ? kOne : static_cast<uint64_t>(ratio);
    Add(r, RoundShiftSat64(static_cast<Int128>(f) * ratio_q32, -32),
        RoundShiftSat64(static_cast<Int128>(g[0]) * ratio_q32, -kBakeGradientFracBits),
        RoundShiftSat64(static_cast<Int128>(g[1]) * ratio_q32, -kBakeGradientFracBits));
    return;
  }
  // The stored factor over the unoccluded one: the link's visibility, which
  // the receiver's children inherit (capped at 2: quadratures differ).
  const UInt128 vis = (static_cast<UInt128>(f) * h.node_corner_count[r] << 32) / den;
  const uint64_t vis_q32 = vis > (static_cast<UInt128>(2) << 32) ? 2 * kOne : static_cast<uint64_t>(vis);
  RefineReceiver(r, source, vis_q32, reverse);
}

void SurfaceEmitterRefine::SendSubtree(uint32_t node, int64_t (*scratch)[3]) {
  Source source{node, scratch, Corners(node, scratch), static_cast<uint64_t>(kOne), false, {0, 0, 0}, 0};
  Bound(source.poly, source.count, source.centre, &source.radius);
  for (uint32_t e = send_offsets_[node]; e < send_offsets_[node + 1]; ++e) SendLink(source, send_[e]);
  const uint32_t first = h_->node_first_child[node];
  for (uint32_t c = first; c < first + h_->node_child_count[node]; ++c) SendSubtree(c, scratch);
}

Status SurfaceEmitterRefine::FirstShot(uint32_t root, const SurfaceEmitterShape& shape, const int64_t* coverage_q32,
                                       int64_t* leaf_irradiance_q32) {
  const BakeHierarchy& h = *h_;
  const uint32_t n = h.node_count(), end = tree_end_[root];
  // How much of each node the emitter covers (area-weighted, as FE's pull).
  for (uint32_t k = end; k-- > root;) {
    if (h.leaf(k)) {
      coverage_mean_q32_[k] = coverage_q32[k];
      continue;
    }
    Int128 sum = 0;
    const uint32_t first = h.node_first_child[k];
    for (uint32_t c = first; c < first + h.node_child_count[k]; ++c)
      sum += static_cast<Int128>(h.node_area[c]) * coverage_mean_q32_[c];
    coverage_mean_q32_[k] = h.node_area[k] == 0 ? 0 : static_cast<int64_t>(sum / h.node_area[k]);
  }
  EmitterClip3 clip;
  clip.Set(shape, drop_axis_[h.node_surface[root]]);
  for (uint32_t k = 0; k < n; ++k) e0_[k] = eu_[k] = ev_[k] = 0;
  // Fig. 5 from the root: fully covered subtrees send as they are; a partly
  // covered node's links get new factors for its clipped part.
  uint32_t stack[kStackNodes];
  int depth = 0;
  stack[depth++] = root;
  needed_ = 0;
  int64_t clipped[kMaxFactorPolygonCorners][3];
  while (depth > 0) {
    const uint32_t s = stack[--depth];
    if (coverage_mean_q32_[s] <= 0) continue;
    if (coverage_mean_q32_[s] >= kOne) {
      SendSubtree(s, clipped);
      continue;
    }
    const int count = clip.Clip(h, *mesh_, s, clipped);
    Source source{s, clipped, count, static_cast<uint64_t>(coverage_mean_q32_[s]), true, {0, 0, 0}, 0};
    Bound(source.poly, source.count, source.centre, &source.radius);
    for (uint32_t e = send_offsets_[s]; e < send_offsets_[s + 1]; ++e) {
      if (count == 0) {
        Send(send_[e], source.coverage_q32);  // a sliver the clip lost
      } else {
        SendLink(source, send_[e]);
      }
    }
    const uint32_t first = h.node_first_child[s];
    for (uint32_t c = first; c < first + h.node_child_count[s]; ++c) {
      if (depth == kStackNodes) return Status(StatusCode::kInternal, "surface emitter: quadtree too deep");
      stack[depth++] = c;
    }
  }
  if (needed_ > pool_.size()) {
    return Status(StatusCode::kOutOfRange,
                  StrFormat("surface emitter (adaptive refine): the polygon needs %zu new links, more than "
                            "the %zu the refine pool holds (EngineOptions::emitter_refine_links)",
                            needed_, pool_.size()));
  }
  for (size_t i = 0; i < needed_; ++i) {
    const NewLink& l = pool_[i];
    e0_[l.receiver] = AddSat64(e0_[l.receiver], l.e0_q32);
    eu_[l.receiver] = AddSat64(eu_[l.receiver], l.eu_q32);
    ev_[l.receiver] = AddSat64(ev_[l.receiver], l.ev_q32);
  }
  last_links_ = static_cast<int>(needed_);
  // Push down as the solver does: each node's field about its surface's
  // origin, a child adds its parent's, a leaf takes the field at its centroid.
  for (uint32_t k = 0; k < n; ++k) {
    const int32_t* uv = &centre_uv_q16_[2 * size_t{k}];
    e0_[k] = SubSat64(e0_[k], GradientTerm(eu_[k], ev_[k], uv));
    const uint32_t parent = h.node_parent[k];
    if (parent != kBakeNoIndex) {
      e0_[k] = AddSat64(e0_[k], e0_[parent]);
      eu_[k] = AddSat64(eu_[k], eu_[parent]);
      ev_[k] = AddSat64(ev_[k], ev_[parent]);
    }
  }
  for (uint32_t k = 0; k < n; ++k) {
    leaf_irradiance_q32[k] =
        h.leaf(k) ? AddSat64(e0_[k], GradientTerm(eu_[k], ev_[k], &centre_uv_q16_[2 * size_t{k}])) : 0;
  }
  return Status::Ok();
}

}  // namespace relight
