// Links of hierarchical radiosity by BF refinement (Hanrahan, Salzman &
// Aupperle 1991): starting from every pair of input surfaces, a pair of nodes
// p, q is split (the larger node first) while the error of the light it would
// carry exceeds epsilon; otherwise it becomes a link at that level. Leaves
// (the mesh patches) cannot split, and a leaf-to-leaf link carries exactly
// the dense matrix's F_ij and F_ji. One link serves both directions, so the
// two factors share their visibility rays.
//
// Beyond HSA's constant irradiance per node, a link's light on an internal
// receiving node varies linearly (the least-squares gradient of the
// point-to-polygon factor over the node's quadrature points): the light next
// to a wall falls off across a ceiling node that touches it, and a constant
// would need that node split down to its leaves. The error estimate is then
//   partly hidden (a few rays disagree):  B_q F_pq            (all of it)
//   in full view:  B_q max(r_pq, kQuadratureError F_pq)
// in both directions, r_pq the largest residual of the linear fit over p's
// points (0 for a leaf p). A node that crosses the other's plane is split.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "form_factors.h"
#include "hierarchy.h"
#include "progress.h"
#include "visibility.h"

namespace relight::baker {

// Relative error of a link in full view that the fit's residuals do not
// show (quadrature, and the source's exitance averaged over its area).
constexpr double kQuadratureError = 0.1;

struct HierarchyLink {
  uint32_t p = 0, q = 0;  // nodes on different surfaces, p < q
  // With visibility. f_pq: fraction of the light leaving p that reaches q,
  // i.e. the mean irradiance on p (lux) per unit exitance of q (lm/m^2).
  double f_pq = 0, f_qp = 0;
  // How that irradiance varies over p (per metre, along p's surface frame
  // u, v, about p's centre); zero for a leaf. Likewise g_qp over q.
  std::array<double, 2> g_pq{}, g_qp{};
};

// The factors of a node pair at their own level, unoccluded: the mean of the
// point-to-polygon factor over the sender's quadrature points, its gradient
// and largest residual over them. Exposed for tests.
struct NodePairFactors {
  double f_pq = 0, f_qp = 0;
  std::array<double, 2> g_pq{}, g_qp{};
  double residual_pq = 0, residual_qp = 0;
  bool faces = false;  // false: neither sees the other (behind or edge-on)
};
NodePairFactors UnoccludedNodeFactors(const Hierarchy& h, const NodeSamples& samples, uint32_t p,
                                      uint32_t q);
// Fraction of rays between the two nodes' points that Embree finds unblocked:
// 16 paired rays; with `adaptive`, where those disagree, all 16 x 16 pairs.
double NodeVisibleFraction(const Hierarchy& h, const NodeSamples& samples, const Visibility& vis,
                           uint32_t p, uint32_t q, bool adaptive = false);

struct NodePair {
  uint32_t p = 0, q = 0;  // surface nodes on different surfaces, p < q
};

// False when one node lies wholly behind the other's plane: no light passes.
bool NodesCanFace(const Hierarchy& h, uint32_t p, uint32_t q);

// adaptive_visibility: 256 rays for the pairs whose 16 disagree (measured
// in docs/hierarchy.md: it barely moves the living room's errors and
// costs about 3x the link time, so it is off by default).
// share_rank / share_ranks: refine only every share_ranks-th root pair
// (by size), from share_rank on; the shares' links together are all of them.
// brightness: per node, an estimate of its exitance (any unit; only F times
// it is compared with epsilon, in the same unit). epsilon: per node, the
// largest error allowed in the light one link brings to it as a receiver
// (link_brightness.h, ReceiverRelativeEstimate). Deterministic: links come
// out sorted by (p, q) whatever the thread count.
std::vector<HierarchyLink> RefineLinks(const Mesh& mesh, const Visibility& vis,
                                       const PatchSampleSets& patch_samples, const Hierarchy& h,
                                       const std::vector<double>& brightness,
                                       const std::vector<double>& epsilon,
                                       bool adaptive_visibility, int threads, Progress* progress,
                                       int share_rank = 0, int share_ranks = 1);
// The same from given node pairs (the clusters' refinement hands its
// surface pairs here), shared between ranks and ordered as RefineLinks does.
std::vector<HierarchyLink> RefineNodePairs(const Mesh& mesh, const Visibility& vis,
                                           const PatchSampleSets& patch_samples,
                                           const Hierarchy& h, const NodeSamples& samples,
                                           std::vector<NodePair> pairs,
                                           const std::vector<double>& brightness,
                                           const std::vector<double>& epsilon,
                                           bool adaptive_visibility, int threads,
                                           Progress* progress, int share_rank = 0,
                                           int share_ranks = 1);
// One bound for every receiver (BF refinement's absolute epsilon).
std::vector<HierarchyLink> RefineLinks(const Mesh& mesh, const Visibility& vis,
                                       const PatchSampleSets& patch_samples, const Hierarchy& h,
                                       const std::vector<double>& brightness, double epsilon,
                                       bool adaptive_visibility, int threads, Progress* progress,
                                       int share_rank = 0, int share_ranks = 1);

}  // namespace relight::baker
