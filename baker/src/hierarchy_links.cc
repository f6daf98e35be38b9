#include "hierarchy_links.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "parallel_for.h"
#include "polygon_factor_kernel.h"
#include "radiosity_vec.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;

double Height(const HierarchyNode& n, const Vec3& y) { return Dot(n.normal, y - n.centre); }

// No corner of b strictly in front of a's plane: they cannot see each other.
bool Behind(const HierarchyNode& a, const HierarchyNode& b) {
  const double tol = 1e-9 * std::max(a.diameter_m, b.diameter_m);
  for (int k = 0; k < b.corner_count; ++k)
    if (Height(a, b.corners[k]) > tol) return false;
  return true;
}

// Corners of b on both sides of a's plane: b's quadrature points may all
// miss the part of b in front of a (a floor running under a sofa's side).
bool Straddles(const HierarchyNode& a, const HierarchyNode& b) {
  const double tol = 1e-9 * std::max(a.diameter_m, b.diameter_m);
  bool front = false, back = false;
  for (int k = 0; k < b.corner_count; ++k) {
    const double height = Height(a, b.corners[k]);
    front = front || height > tol;
    back = back || height < -tol;
  }
  return front && back;
}

bool Near(const HierarchyNode& a, const HierarchyNode& b) {
  return Length(a.centre - b.centre) < 2.0 * std::max(a.diameter_m, b.diameter_m);
}

// The point-to-polygon factor from `from`'s points to `to`: its weighted
// mean, and for an internal node the weighted least-squares gradient about
// the node's centre (the mean is kept, so the light's total is unchanged)
// and the fit's largest residual.
void Unoccluded(const Hierarchy& h, const HierarchyNode& from,
                const std::vector<PatchSample>& from_samples, const HierarchyNode& to,
                double* mean, std::array<double, 2>* gradient, double* residual) {
  constexpr int kMaxPoints = 32;
  double f[kMaxPoints];
  const size_t count = std::min<size_t>(from_samples.size(), kMaxPoints);
  double m = 0;
  PointsToPolygonFormFactors(from_samples.data(), count, from.normal, to.corners.data(), to.corner_count,
                             to.normal, f);
  for (size_t k = 0; k < count; ++k) m += from_samples[k].weight * f[k];
  *mean = m;
  *gradient = {0, 0};
  *residual = 0;
  if (from.leaf()) return;  // a leaf's mean is all the solve resolves
  const auto c = h.PlaneCoords(from.surface, from.centre);
  double suu = 0, suv = 0, svv = 0, su = 0, sv = 0;
  double du[kMaxPoints], dv[kMaxPoints];
  for (size_t k = 0; k < count; ++k) {
    const auto x = h.PlaneCoords(from.surface, from_samples[k].point);
    du[k] = x[0] - c[0];
    dv[k] = x[1] - c[1];
    const double w = from_samples[k].weight;
    suu += w * du[k] * du[k];
    suv += w * du[k] * dv[k];
    svv += w * dv[k] * dv[k];
    su += w * du[k] * (f[k] - m);
    sv += w * dv[k] * (f[k] - m);
  }
  const double det = suu * svv - suv * suv;
  if (det > 1e-12 * (suu * svv)) {
    (*gradient)[0] = (svv * su - suv * sv) / det;
    (*gradient)[1] = (suu * sv - suv * su) / det;
  }
  for (size_t k = 0; k < count; ++k) {
    const double fit = m + (*gradient)[0] * du[k] + (*gradient)[1] * dv[k];
    *residual = std::max(*residual, std::abs(f[k] - fit));
  }
}

// Sample s of one node is paired with sample Pair(s) of the other: a fixed
// permutation (multiplier coprime with the count), so the rays spread.
size_t Pair(size_t s, size_t count) {
  for (size_t m : {7u, 5u, 3u, 11u, 13u})
    if (std::gcd(m, count) == 1) return (s * m + 1) % count;
  return s % count;
}


class Refiner {
 public:
  Refiner(const Mesh& mesh, const Visibility& vis, const PatchSampleSets& patch_samples,
          const Hierarchy& h, const NodeSamples& samples, const std::vector<double>& brightness,
          const std::vector<double>& epsilon, bool adaptive)
      : mesh_(mesh),
        vis_(vis),
        patch_samples_(patch_samples),
        h_(h),
        samples_(samples),
        brightness_(brightness),
        epsilon_(epsilon),
        adaptive_(adaptive) {}

  void Refine(uint32_t p, uint32_t q, std::vector<HierarchyLink>* out) const {
    const HierarchyNode& np = h_.nodes[p];
    const HierarchyNode& nq = h_.nodes[q];
    if (np.leaf() && nq.leaf()) {
      double f_pq, f_qp;
      if (PatchPairFormFactors(mesh_, vis_, patch_samples_, np.patch, nq.patch, &f_pq, &f_qp) &&
          (f_pq > 0 || f_qp > 0)) {
        out->push_back({p, q, f_pq, f_qp});
      }
      return;
    }
    const NodePairFactors f = UnoccludedNodeFactors(h_, samples_, p, q);
    if (!f.faces) return;
    const bool p_straddles = !np.leaf() && Straddles(nq, np);
    const bool q_straddles = !nq.leaf() && Straddles(np, nq);
    // In full view, the error is what the linear fit over the receiver
    // misses. A few rays decide a partly hidden pair's visibility only
    // roughly: then all of its light may be wrong. Rays are only cast for a
    // pair that would otherwise become a link.
    // Each direction against its receiver's own bound.
    const bool in_view =
        std::max(f.residual_pq, kQuadratureError * f.f_pq) * brightness_[q] > epsilon_[p] ||
        std::max(f.residual_qp, kQuadratureError * f.f_qp) * brightness_[p] > epsilon_[q];
    bool split = in_view || p_straddles || q_straddles;
    double v = 1;
    if (!split) {
      v = NodeVisibleFraction(h_, samples_, vis_, p, q, adaptive_);
      split = v < 1 &&
              (f.f_pq * brightness_[q] > epsilon_[p] || f.f_qp * brightness_[p] > epsilon_[q]);
    }
    if (split) {
      // Split a node that crosses the other's plane, else the larger one (a
      // leaf cannot split).
      const bool split_p =
          p_straddles || (!q_straddles && !np.leaf() && (nq.leaf() || np.area_m2 >= nq.area_m2));
      const HierarchyNode& parent = split_p ? np : nq;
      for (uint32_t c = parent.first_child; c < parent.first_child + parent.child_count; ++c) {
        if (split_p) {
          Refine(c, q, out);
        } else {
          Refine(p, c, out);
        }
      }
      return;
    }
    if (v > 0) {
      out->push_back({p, q, f.f_pq * v, f.f_qp * v, {f.g_pq[0] * v, f.g_pq[1] * v},
                      {f.g_qp[0] * v, f.g_qp[1] * v}});
    }
  }

 private:
  const Mesh& mesh_;
  const Visibility& vis_;
  const PatchSampleSets& patch_samples_;
  const Hierarchy& h_;
  const NodeSamples& samples_;
  const std::vector<double>& brightness_;
  const std::vector<double>& epsilon_;
  bool adaptive_;
};

}  // namespace

bool NodesCanFace(const Hierarchy& h, uint32_t p, uint32_t q) {
  return !Behind(h.nodes[p], h.nodes[q]) && !Behind(h.nodes[q], h.nodes[p]);
}

NodePairFactors UnoccludedNodeFactors(const Hierarchy& h, const NodeSamples& samples, uint32_t p,
                                      uint32_t q) {
  NodePairFactors out;
  const HierarchyNode& np = h.nodes[p];
  const HierarchyNode& nq = h.nodes[q];
  if (Behind(np, nq) || Behind(nq, np)) return out;
  const bool near = Near(np, nq);
  Unoccluded(h, np, near ? samples.fine(p) : samples.coarse(p), nq, &out.f_pq, &out.g_pq,
             &out.residual_pq);
  Unoccluded(h, nq, near ? samples.fine(q) : samples.coarse(q), np, &out.f_qp, &out.g_qp,
             &out.residual_qp);
  out.faces = out.f_pq > 0 || out.f_qp > 0;
  return out;
}

double NodeVisibleFraction(const Hierarchy& h, const NodeSamples& samples, const Visibility& vis,
                           uint32_t p, uint32_t q, bool adaptive) {
  const HierarchyNode& np = h.nodes[p];
  const HierarchyNode& nq = h.nodes[q];
  // Always the fine points (16 rays): a hidden corner of a big node must
  // show up as partial visibility, which refines the link.
  const std::vector<PatchSample>& sp = samples.fine(p);
  const std::vector<PatchSample>& sq = samples.fine(q);
  int valid = 0;
  VisibleCounter counter(vis);
  for (size_t s = 0; s < sp.size(); ++s) {
    const Vec3& x = sp[s].point;
    const Vec3& y = sq[Pair(s, sq.size())].point;
    if (Height(nq, x) <= 0 || Height(np, y) <= 0) continue;
    ++valid;
    counter.Add(vis.Offset(x, np.normal), vis.Offset(y, nq.normal));
  }
  const int visible = counter.visible();
  if (valid == 0) return 1.0;
  if (!adaptive || visible == 0 || visible == valid) return static_cast<double>(visible) / valid;
  // The 16 rays disagree: the pair is partly hidden and 16 rays give its
  // visibility only to about +-1/8. Every point of p against every point of
  // q (256 rays, weighted by the points' quadrature weights) pins it down.
  double seen = 0, total = 0;
  for (const PatchSample& a : sp) {
    if (Height(nq, a.point) <= 0) continue;
    const Vec3 x = vis.Offset(a.point, np.normal);
    for (const PatchSample& b : sq) {
      if (Height(np, b.point) <= 0) continue;
      const double w = a.weight * b.weight;
      total += w;
      if (vis.Visible(x, vis.Offset(b.point, nq.normal))) seen += w;
    }
  }
  return total > 0 ? seen / total : static_cast<double>(visible) / valid;
}

std::vector<HierarchyLink> RefineNodePairs(const Mesh& mesh, const Visibility& vis,
                                           const PatchSampleSets& patch_samples,
                                           const Hierarchy& h, const NodeSamples& samples,
                                           std::vector<NodePair> node_pairs,
                                           const std::vector<double>& brightness,
                                           const std::vector<double>& epsilon, bool adaptive,
                                           int threads, Progress* progress, int share_rank,
                                           int share_ranks) {
  const Refiner refiner(mesh, vis, patch_samples, h, samples, brightness, epsilon, adaptive);
  // The biggest first, so the workers finish together. Sorted in place (a
  // venue's walk hands on tens of millions of pairs).
  std::vector<NodePair>& pairs = node_pairs;
  const auto weight = [&h](const NodePair& n) {
    return h.nodes[n.p].area_m2 * h.nodes[n.q].area_m2;
  };
  std::sort(pairs.begin(), pairs.end(), [&weight](const NodePair& x, const NodePair& y) {
    const double wx = weight(x), wy = weight(y);
    return wx != wy ? wx > wy : (x.p != y.p ? x.p < y.p : x.q < y.q);
  });
  // A distributed bake's share: dealt round the ranks by size, so each gets
  // big and small pairs alike.
  if (share_ranks > 1) {
    size_t kept = 0;
    for (size_t k = 0; k < pairs.size(); ++k)
      if (static_cast<int>(k % static_cast<size_t>(share_ranks)) == share_rank)
        pairs[kept++] = pairs[k];
    pairs.resize(kept);
  }
  // Progress in units of the pairs' area products (a rough measure of their work).
  double total_weight = 0;
  for (const NodePair& r : pairs) total_weight += weight(r);
  const auto units = [&](size_t k) {
    return 1 + static_cast<size_t>(std::llround(1e5 * weight(pairs[k]) / total_weight));
  };
  size_t total_units = 0;
  for (size_t k = 0; k < pairs.size(); ++k) total_units += units(k);
  if (progress) progress->Begin("links (hierarchical)", total_units);
  const int workers = ResolveThreads(threads);
  std::vector<std::vector<HierarchyLink>> per_worker(static_cast<size_t>(workers));
  ParallelFor(pairs.size(), workers, [&](size_t k, int worker) {
    refiner.Refine(pairs[k].p, pairs[k].q, &per_worker[static_cast<size_t>(worker)]);
    if (progress) progress->Advance(units(k));
  });
  if (progress) progress->End();

  std::vector<HierarchyLink> links;
  size_t count = 0;
  for (const auto& w : per_worker) count += w.size();
  links.reserve(count);
  for (auto& w : per_worker) {
    links.insert(links.end(), w.begin(), w.end());
    std::vector<HierarchyLink>().swap(w);
  }
  std::sort(links.begin(), links.end(), [](const HierarchyLink& x, const HierarchyLink& y) {
    return x.p != y.p ? x.p < y.p : x.q < y.q;
  });
  return links;
}

std::vector<HierarchyLink> RefineLinks(const Mesh& mesh, const Visibility& vis,
                                       const PatchSampleSets& patch_samples, const Hierarchy& h,
                                       const std::vector<double>& brightness,
                                       const std::vector<double>& epsilon, bool adaptive,
                                       int threads, Progress* progress, int share_rank,
                                       int share_ranks) {
  // Every pair of surfaces that can face each other.
  std::vector<NodePair> pairs;
  const size_t surfaces = h.surface_count();
  for (size_t a = 0; a < surfaces; ++a) {
    for (size_t b = a + 1; b < surfaces; ++b) {
      if (!NodesCanFace(h, h.root(a), h.root(b))) continue;
      pairs.push_back({h.root(a), h.root(b)});
    }
  }
  return RefineNodePairs(mesh, vis, patch_samples, h, NodeSamples(h, patch_samples),
                         std::move(pairs), brightness, epsilon, adaptive, threads, progress,
                         share_rank, share_ranks);
}

std::vector<HierarchyLink> RefineLinks(const Mesh& mesh, const Visibility& vis,
                                       const PatchSampleSets& patch_samples, const Hierarchy& h,
                                       const std::vector<double>& brightness, double epsilon,
                                       bool adaptive, int threads, Progress* progress,
                                       int share_rank, int share_ranks) {
  return RefineLinks(mesh, vis, patch_samples, h, brightness,
                     std::vector<double>(h.nodes.size(), epsilon), adaptive, threads, progress,
                     share_rank, share_ranks);
}

}  // namespace relight::baker
