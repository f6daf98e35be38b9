// Adaptive refine's sending (surface_emitter_refine.h): the sources the
// walk listed, in two parts, each into its own pool and arrays; per link
// FE's share or new factors. Scaling and overflow as in
// surface_emitter_refine.cc.
#include <algorithm>
#include <cstddef>

#include "emitter_clip3.h"
#include "point_polygon_factor.h"
#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"
#include "surface_emitter_refine.h"

namespace relight {

void SurfaceEmitterRefine::Add(Part& part, uint32_t receiver, int64_t e0, int64_t eu, int64_t ev) const {
  if (part.needed < part.pool.size()) part.pool[part.needed] = {receiver, e0, eu, ev};
  ++part.needed;  // past the pool: only counts what the placement would need
}

void SurfaceEmitterRefine::Send(Part& part, uint32_t link_side, uint64_t ratio_q32,
                                const int64_t* moment_q32) const {
  const BakeHierarchy& h = *h_;
  const uint32_t link = link_side >> 1;
  const bool from_p = (link_side & 1) != 0;
  const uint32_t r = from_p ? h.link_q[link] : h.link_p[link];
  const uint32_t f = from_p ? h.link_f_qp[link] : h.link_f_pq[link];
  const int32_t* g = from_p ? &h.link_g_qp[2 * size_t{link}] : &h.link_g_pq[2 * size_t{link}];
  part.e0[r] = AddSat64(part.e0[r], RoundShiftSat64(static_cast<Int128>(f) * ratio_q32, -32));
  if (moment_q32 != nullptr) part.e0[r] = AddSat64(part.e0[r], MomentTerm(link, from_p, moment_q32));
  if (g[0] != 0 || g[1] != 0) {
    part.eu[r] = AddSat64(part.eu[r], RoundShiftSat64(static_cast<Int128>(g[0]) * ratio_q32, -kBakeGradientFracBits));
    part.ev[r] = AddSat64(part.ev[r], RoundShiftSat64(static_cast<Int128>(g[1]) * ratio_q32, -kBakeGradientFracBits));
  }
}

// FE's source-moment term (surface_emitter_moments.h) for one link side of
// a partly covered inner node: f (g_rev / f_rev) . m, the part of the node
// the receiver sees best against its mean, so an unrefined link sends what
// FE's gathers would. g_rev (Q8.23 per metre) . m (Q32 x m) is Q55, rounded
// to Q32 (saturated: < 2^63); f / f_rev as Q32 (f < 2^32, so the quotient
// of f 2^32 fits 64 bits); their product < 2^127 in 128 bits.
int64_t SurfaceEmitterRefine::MomentTerm(uint32_t link, bool from_p, const int64_t* moment_q32) const {
  const BakeHierarchy& h = *h_;
  const uint64_t f = from_p ? h.link_f_qp[link] : h.link_f_pq[link];
  const uint64_t f_rev = from_p ? h.link_f_pq[link] : h.link_f_qp[link];
  if (f == 0 || f_rev == 0) return 0;  // the solver's rule: no reverse factor, no term
  const int32_t* g_rev = from_p ? &h.link_g_pq[2 * size_t{link}] : &h.link_g_qp[2 * size_t{link}];
  const int64_t gm_q32 = RoundShiftSat64(
      static_cast<Int128>(g_rev[0]) * moment_q32[0] + static_cast<Int128>(g_rev[1]) * moment_q32[1],
      -kBakeGradientFracBits);
  const uint64_t ratio_q32 = (f << 32) / f_rev;
  return RoundShiftSat64(static_cast<Int128>(gm_q32) * ratio_q32, -32);
}

// Below a receiver the stored link treated as one node: each child gets the
// emitter's light at its own points, with the link's visibility (route (a)).
void SurfaceEmitterRefine::RefineReceiver(Part& part, uint32_t node, const Source& source,
                                          uint64_t visibility_q32, uint64_t reverse_q32) const {
  const BakeHierarchy& h = *h_;
  if (!h.leaf(node) && ((reverse_q32 * source.coverage_q32) >> 32) >= refine_threshold_q32_) {
    const uint32_t first = h.node_first_child[node];
    for (uint32_t c = first; c < first + h.node_child_count[node]; ++c) {
      const uint64_t share = static_cast<uint64_t>((static_cast<UInt128>(reverse_q32) * h.node_area[c]) / h.node_area[node]);
      RefineReceiver(part, c, source, visibility_q32, share);
    }
    return;
  }
  if (part.needed >= part.pool.size()) return Add(part, node, 0, 0, 0);
  // An inner node left here keeps the light's slope over it, as a stored
  // link's gradient does; a leaf takes its mean.
  int64_t slope[2] = {0, 0};
  const uint64_t sum =
      SumFactorsQ32(node, source.poly, source.count, source.centre, source.radius, h.leaf(node) ? nullptr : slope);
  const uint64_t mean = sum / static_cast<uint64_t>(h.node_corner_count[node]);
  Add(part, node, RoundShiftSat64(static_cast<Int128>(mean) * visibility_q32, -32),
      RoundShiftSat64(static_cast<Int128>(slope[0]) * visibility_q32, -32),
      RoundShiftSat64(static_cast<Int128>(slope[1]) * visibility_q32, -32));
}

// One link of an emitting node: FE's share where it carries little of the
// emitter's light (BF's F x B below the threshold), else new factors.
void SurfaceEmitterRefine::SendLink(Part& part, const Source& source, uint32_t link_side) const {
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
  if (!refine_source && !refine_receiver) return Send(part, link_side, cov, source.moment_q32);
  if (part.needed >= part.pool.size()) {  // over: count, do not compute
    if (!refine_receiver) return Add(part, r, 0, 0, 0);
    return RefineReceiver(part, r, source, 0, reverse);
  }
  int64_t whole[kBakeMaxNodeCorners][3], whole_centre[3], whole_radius = 0;
  const int whole_count = Corners(source.node, whole);
  Bound(whole, whole_count, whole_centre, &whole_radius);
  const uint64_t den = SumFactorsQ32(r, whole, whole_count, whole_centre, whole_radius);
  // The receiver sees the node only edge-on at its points: keep FE's share.
  if (den == 0) return Send(part, link_side, cov, source.moment_q32);
  // The same points for both, so the ratio is the emitter's share as r sees it.
  const uint64_t num =
      source.partial ? SumFactorsQ32(r, source.poly, source.count, whole_centre, whole_radius) : den;
  if (!refine_receiver) {
    const UInt128 ratio = (static_cast<UInt128>(num) << 32) / den;
    const int32_t* g = from_p ? &h.link_g_qp[2 * size_t{link}] : &h.link_g_pq[2 * size_t{link}];
    const uint64_t ratio_q32 = ratio > (static_cast<UInt128>(1) << 32) ? kOne : static_cast<uint64_t>(ratio);
    Add(part, r, RoundShiftSat64(static_cast<Int128>(f) * ratio_q32, -32),
        RoundShiftSat64(static_cast<Int128>(g[0]) * ratio_q32, -kBakeGradientFracBits),
        RoundShiftSat64(static_cast<Int128>(g[1]) * ratio_q32, -kBakeGradientFracBits));
    return;
  }
  // The stored factor over the unoccluded one: the link's visibility, which
  // the receiver's children inherit (capped at 2: quadratures differ).
  const UInt128 vis = (static_cast<UInt128>(f) * h.node_corner_count[r] << 32) / den;
  const uint64_t vis_q32 = vis > (static_cast<UInt128>(2) << 32) ? 2 * kOne : static_cast<uint64_t>(vis);
  RefineReceiver(part, r, source, vis_q32, reverse);
}

// A fully covered node and all its subtree, in the order the sending used
// to recurse through it.
void SurfaceEmitterRefine::AddJobs(uint32_t node) {
  jobs_[job_count_++] = node;
  const uint32_t first = h_->node_first_child[node];
  for (uint32_t c = first; c < first + h_->node_child_count[node]; ++c) AddJobs(c);
}

// Jobs part, part + kParts, ...: whole nodes through their links as they
// are (new factors only where the receiver looks large from them), cut
// nodes with their clipped polygon.
void SurfaceEmitterRefine::RunPart(int p, const EmitterClip3* clip) {
  const BakeHierarchy& h = *h_;
  Part& part = parts_[p];
  part.needed = 0;
  std::fill(part.e0.begin(), part.e0.end(), 0);
  std::fill(part.eu.begin(), part.eu.end(), 0);
  std::fill(part.ev.begin(), part.ev.end(), 0);
  int64_t polygon[kMaxFactorPolygonCorners][3];
  for (uint32_t j = static_cast<uint32_t>(p); j < job_count_; j += kParts) {
    const uint32_t s = jobs_[j] & ~kPartialJob;
    const bool partial = (jobs_[j] & kPartialJob) != 0;
    if (clip == nullptr) {  // fractional emissivity: the node's covered share through every link
      const uint64_t share =
          partial ? static_cast<uint64_t>(coverage_mean_q32_[s]) : static_cast<uint64_t>(kOne);
      for (uint32_t e = send_offsets_[s]; e < send_offsets_[s + 1]; ++e) Send(part, send_[e], share);
      continue;
    }
    const int count = partial ? clip->Clip(h, *mesh_, s, polygon) : Corners(s, polygon);
    const bool moment = partial && !h.leaf(s);  // a whole node's or a leaf's is zero
    Source source{s,
                  polygon,
                  count,
                  partial ? static_cast<uint64_t>(coverage_mean_q32_[s]) : static_cast<uint64_t>(kOne),
                  partial,
                  {0, 0, 0},
                  0,
                  moment ? &coverage_moment_q32_[2 * size_t{s}] : nullptr};
    Bound(source.poly, source.count, source.centre, &source.radius);
    for (uint32_t e = send_offsets_[s]; e < send_offsets_[s + 1]; ++e) {
      if (count == 0) {
        Send(part, send_[e], source.coverage_q32, source.moment_q32);  // a sliver the clip lost
      } else {
        SendLink(part, source, send_[e]);
      }
    }
  }
}

}  // namespace relight
