#include "cluster_links.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>

#include "form_factors.h"
#include "parallel_for.h"
#include "radiosity_vec.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;

constexpr double kPi = 3.14159265358979323846;
// Relative error of a cluster link's light when the elements are far apart
// against their size: the six bins' orientation (exact square to the axes,
// up to ~0.7 for a member at 45 degrees to all three) and 16 rays' visibility.
constexpr double kClusterError = 0.2;

// Every corner of the box at or behind the node's plane: nothing in the box
// can exchange light with the node.
bool BoxBehind(const HierarchyNode& node, const Vec3& lo, const Vec3& hi) {
  const double tol = 1e-9 * node.diameter_m;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 x{(corner & 1) ? hi[0] : lo[0], (corner & 2) ? hi[1] : lo[1],
                 (corner & 4) ? hi[2] : lo[2]};
    if (Dot(node.normal, x - node.centre) > tol) return false;
  }
  return true;
}

}  // namespace

double SurfaceFactor(const Hierarchy& h, const ClusterTree& tree, uint32_t node, uint32_t cluster) {
  const HierarchyNode& n = h.nodes[node];
  const Vec3 c = ElementCentre(h, tree, cluster);
  if (Dot(n.normal, c - n.centre) <= 0) return -1;
  const Vec3 facing = Normalized(n.centre - c);
  return PointToPolygonFormFactor(c, facing, n.corners.data(), n.corner_count, n.normal);
}

namespace {

// What the walk decides, before any ray: candidate links (a, b; a < b) and
// surface pairs, 8 bytes each. A link's direction and factors (a 48-byte
// ClusterLink) are made afterwards and kept only where rays join the pair:
// on the 100k venue's second pass 50-100 million candidates, 8.7 million
// kept. Held as ClusterLinks from the start, the candidates took 4.6 GB at
// the join (the peak of the whole bake), and their array's touched pages
// stayed resident for the rest of it (docs/venue.md, "Memory of the
// cluster walk").
struct WalkFound {
  std::vector<NodePair> links;
  std::vector<NodePair> node_pairs;
  size_t pairs_visited = 0;
};

// Candidates given their factors per block, so the 48-byte links exist
// only a block at a time before the ones without light are dropped.
constexpr size_t kFactorBlock = size_t{1} << 20;

class ClusterRefiner {
 public:
  ClusterRefiner(const Hierarchy& h, const ClusterTree& tree, const std::vector<double>& brightness,
                 const std::vector<double>& epsilon)
      : h_(h), tree_(tree), brightness_(brightness), epsilon_(epsilon) {
    // Per cluster: the members' brightness x area summed (what its light can
    // be at most, x 1/(pi d²)), and the tightest of their roots' bounds (a
    // root's bound is already the least of its leaves').
    const size_t count = tree.clusters.size();
    flux_.assign(count, 0);
    bound_.assign(count, 0);
    for (size_t c = count; c-- > 0;) {
      const Cluster& cluster = tree.clusters[c];
      double flux = 0, bound = std::numeric_limits<double>::max();
      for (uint32_t child : cluster.children) {
        flux += Flux(child);
        bound = std::min(bound, Bound(child));
      }
      flux_[c] = flux;
      bound_[c] = bound;
    }
  }

  void Visit(uint32_t x, uint32_t y, WalkFound* out) {
    Walk(x, y, out, [&](uint32_t a, uint32_t b) { Visit(a, b, out); });
  }

  // What the walk does next, in its order: a pair to walk (kVisit), or a
  // link or node pair already decided at the top levels.
  enum class TaskKind : uint8_t { kVisit, kLink, kNodePair };
  struct Task {
    uint32_t x, y;
    TaskKind kind;
  };
  // The walk's first `levels` levels on the caller: a pair that splits is
  // counted and expanded here, anything else becomes a task. Visiting the
  // tasks in order and joining what they find gives the serial walk's
  // links and pairs in the serial walk's order.
  void Expand(uint32_t x, uint32_t y, int levels, std::vector<Task>* tasks, size_t* visited) {
    if (levels == 0) {
      tasks->push_back({x, y, TaskKind::kVisit});
      return;
    }
    WalkFound here;  // at most one link or pair: a pair that splits emits none
    Walk(x, y, &here, [&](uint32_t a, uint32_t b) { Expand(a, b, levels - 1, tasks, visited); });
    *visited += here.pairs_visited;
    for (const NodePair& l : here.links) tasks->push_back({l.p, l.q, TaskKind::kLink});
    for (const NodePair& p : here.node_pairs) tasks->push_back({p.p, p.q, TaskKind::kNodePair});
  }

 private:
  // One step of the walk from the pair (x, y): a link, a surface pair, or
  // nothing; or the pairs of its split, each handed to recurse(a, b).
  template <typename Recurse>
  void Walk(uint32_t x, uint32_t y, WalkFound* out, Recurse recurse) {
    ++out->pairs_visited;
    if (x == y) {
      if (!IsCluster(x)) return;  // a planar surface does not see itself
      const Cluster& c = tree_.clusters[ClusterIndex(x)];
      recurse(c.children[0], c.children[0]);
      recurse(c.children[1], c.children[1]);
      recurse(c.children[0], c.children[1]);
      return;
    }
    if (!IsCluster(x) && !IsCluster(y)) {
      // Pairs that cannot face each other would come back without links.
      if (NodesCanFace(h_, x, y)) out->node_pairs.push_back({std::min(x, y), std::max(x, y)});
      return;
    }
    if (Hidden(x, y) || Hidden(y, x)) return;
    const double rx = ElementRadius(h_, tree_, x), ry = ElementRadius(h_, tree_, y);
    if (Linkable(x, y, rx, ry)) {
      out->links.push_back({std::min(x, y), std::max(x, y)});
      return;
    }
    // Split the larger; a surface leaf cannot split. (Splitting a cluster
    // first wherever it can, so that surfaces meet clusters only whole,
    // gave 2.2x the links between the hall's surfaces and the seats on the
    // 3000-triangle venue: docs/venue.md.)
    const bool x_splits = Splits(x) && (!Splits(y) || rx >= ry);
    const uint32_t parent = x_splits ? x : y, other = x_splits ? y : x;
    if (IsCluster(parent)) {
      for (uint32_t child : tree_.clusters[ClusterIndex(parent)].children) recurse(child, other);
    } else {
      const HierarchyNode& node = h_.nodes[parent];
      for (uint32_t c = node.first_child; c < node.first_child + node.child_count; ++c) recurse(c, other);
    }
  }

  double Flux(uint32_t e) const {
    return IsCluster(e) ? flux_[ClusterIndex(e)] : brightness_[e] * h_.nodes[e].area_m2;
  }
  double Bound(uint32_t e) const { return IsCluster(e) ? bound_[ClusterIndex(e)] : epsilon_[e]; }
  bool Splits(uint32_t e) const { return IsCluster(e) || !h_.nodes[e].leaf(); }

  // Both directions' error estimates (cluster_links.h) within their
  // receivers' bounds.
  bool Linkable(uint32_t x, uint32_t y, double rx, double ry) const {
    const Vec3 cx = ElementCentre(h_, tree_, x), cy = ElementCentre(h_, tree_, y);
    const double r = Length(cy - cx);
    if (!(r > rx + ry)) return false;
    return Error(y, x, r, ry, rx) <= Bound(x) && Error(x, y, r, rx, ry) <= Bound(y);
  }
  // Of `from`'s light arriving at `to` (radii r_from, r_to; centres r apart).
  double Error(uint32_t from, uint32_t to, double r, double r_from, double r_to) const {
    if (IsCluster(from)) {
      return Flux(from) / (kPi * r * r) * std::max(kClusterError, 2 * (r_to + r_from) / r);
    }
    const double f = SurfaceFactor(h_, tree_, from, to);
    if (f < 0) return std::numeric_limits<double>::infinity();
    return brightness_[from] * f * std::max(kClusterError, 2 * r_to / r);
  }
  // y (a cluster) wholly behind node x.
  bool Hidden(uint32_t x, uint32_t y) const {
    if (IsCluster(x) || !IsCluster(y)) return false;
    const Cluster& c = tree_.clusters[ClusterIndex(y)];
    return BoxBehind(h_.nodes[x], c.lo, c.hi);
  }

  const Hierarchy& h_;
  const ClusterTree& tree_;
  const std::vector<double>& brightness_;
  const std::vector<double>& epsilon_;
  std::vector<double> flux_, bound_;
};

// Up to kClusterSamples points of an element with their normals.
int ElementPoints(const Hierarchy& h, const ClusterTree& tree, const NodeSamples& samples,
                  uint32_t e, std::array<ClusterPoint, kClusterSamples>* out) {
  if (IsCluster(e)) {
    *out = tree.clusters[ClusterIndex(e)].samples;
    return kClusterSamples;
  }
  const std::vector<PatchSample>& s = samples.fine(e);
  const int count = static_cast<int>(std::min<size_t>(s.size(), kClusterSamples));
  for (int k = 0; k < count; ++k)
    (*out)[static_cast<size_t>(k)] = {s[static_cast<size_t>(k)].point, h.nodes[e].normal};
  return count;
}

// Fraction of rays between the two elements' points that arrive, over
// pairs of points whose surfaces face each other (a member facing away
// takes no part in this link's light: the bins weigh orientation, and a ray
// from the back of a box's face would start inside the box). 16 pairs in a
// fixed spread first; if none of them face each other, the first 16 of all
// pairs that do; none at all: nothing passes.
double VisibleFraction(const Hierarchy& h, const ClusterTree& tree, const NodeSamples& samples,
                       const Visibility& vis, uint32_t a, uint32_t b) {
  std::array<ClusterPoint, kClusterSamples> pa, pb;
  const int na = ElementPoints(h, tree, samples, a, &pa);
  const int nb = ElementPoints(h, tree, samples, b, &pb);
  const auto faces = [](const ClusterPoint& x, const ClusterPoint& y) {
    return Dot(x.normal, y.point - x.point) > 0 && Dot(y.normal, x.point - y.point) > 0;
  };
  int valid = 0;
  VisibleCounter counter(vis);
  const auto cast = [&](const ClusterPoint& x, const ClusterPoint& y) {
    ++valid;
    counter.Add(vis.Offset(x.point, x.normal), vis.Offset(y.point, y.normal));
  };
  const int rays = std::max(na, nb);
  for (int k = 0; k < rays && na > 0 && nb > 0; ++k) {
    // Paired by a fixed stride coprime with 16, so the rays spread.
    const ClusterPoint& x = pa[static_cast<size_t>(k % na)];
    const ClusterPoint& y = pb[static_cast<size_t>((7 * k + 3) % nb)];
    if (faces(x, y)) cast(x, y);
  }
  for (int i = 0; i < na && valid == 0; ++i) {
    for (int j = 0; j < nb && valid < kClusterSamples; ++j) {
      if (faces(pa[static_cast<size_t>(i)], pb[static_cast<size_t>(j)]))
        cast(pa[static_cast<size_t>(i)], pb[static_cast<size_t>(j)]);
    }
  }
  const int visible = counter.visible();
  return valid > 0 ? static_cast<double>(visible) / valid : 0.0;
}

}  // namespace

Vec3 ElementCentre(const Hierarchy& h, const ClusterTree& tree, uint32_t e) {
  return IsCluster(e) ? tree.clusters[ClusterIndex(e)].centre : h.nodes[e].centre;
}

double ElementRadius(const Hierarchy& h, const ClusterTree& tree, uint32_t e) {
  if (IsCluster(e)) return tree.clusters[ClusterIndex(e)].radius_m;
  const HierarchyNode& n = h.nodes[e];
  double r = 0;
  for (int k = 0; k < n.corner_count; ++k)
    r = std::max(r, Length(n.corners[static_cast<size_t>(k)] - n.centre));
  return r;
}

ClusteredRefinement RefineClusters(const Hierarchy& h, const ClusterTree& tree,
                                   const NodeSamples& samples, const Visibility& vis,
                                   const std::vector<double>& brightness,
                                   const std::vector<double>& epsilon, int threads,
                                   Progress* progress, int walk_levels) {
  ClusteredRefinement out;
  if (tree.empty()) return out;
  // The walk casts no ray, but its link tests (a form factor each) took
  // 57 s of one core on the 100 000-triangle venue (6 s on the 12 000),
  // twice a bake: its top levels are cut into tasks for every thread,
  // joined in the serial order (docs/venue.md).
  ClusterRefiner refiner(h, tree, brightness, epsilon);
  const uint32_t root = tree.root_element(h);
  std::vector<ClusterRefiner::Task> tasks;
  refiner.Expand(root, root, walk_levels, &tasks, &out.pairs_visited);
  // Each thread appends to its own arrays (large ones: returned to the
  // system when freed, where a vector per task would leave the heap
  // holding their bytes for the rest of the bake); each task notes where
  // its part lies.
  struct Piece {
    int worker;
    size_t links_begin, links_end, pairs_begin, pairs_end;
  };
  const int workers = ResolveThreads(threads);
  std::vector<WalkFound> found(static_cast<size_t>(workers));
  std::vector<Piece> pieces(tasks.size());
  ParallelFor(tasks.size(), workers, [&](size_t k, int worker) {
    const ClusterRefiner::Task& t = tasks[k];
    WalkFound& f = found[static_cast<size_t>(worker)];
    Piece& piece = pieces[k];
    piece.worker = worker;
    piece.links_begin = f.links.size();
    piece.pairs_begin = f.node_pairs.size();
    switch (t.kind) {
      case ClusterRefiner::TaskKind::kVisit:
        refiner.Visit(t.x, t.y, &f);
        break;
      case ClusterRefiner::TaskKind::kLink:
        f.links.push_back({t.x, t.y});
        break;
      case ClusterRefiner::TaskKind::kNodePair:
        f.node_pairs.push_back({t.x, t.y});
        break;
    }
    piece.links_end = f.links.size();
    piece.pairs_end = f.node_pairs.size();
  });
  size_t links = 0, pairs = 0;
  for (const WalkFound& f : found) {
    links += f.links.size();
    pairs += f.node_pairs.size();
    out.pairs_visited += f.pairs_visited;
  }
  std::vector<NodePair> candidates;
  candidates.reserve(links);
  out.node_pairs.reserve(pairs);
  for (const Piece& piece : pieces) {
    const WalkFound& f = found[static_cast<size_t>(piece.worker)];
    candidates.insert(candidates.end(), f.links.begin() + static_cast<ptrdiff_t>(piece.links_begin),
                      f.links.begin() + static_cast<ptrdiff_t>(piece.links_end));
    out.node_pairs.insert(out.node_pairs.end(), f.node_pairs.begin() + static_cast<ptrdiff_t>(piece.pairs_begin),
                          f.node_pairs.begin() + static_cast<ptrdiff_t>(piece.pairs_end));
  }
  std::vector<WalkFound>().swap(found);
  std::sort(candidates.begin(), candidates.end(), [](const NodePair& x, const NodePair& y) {
    return x.p != y.p ? x.p < y.p : x.q < y.q;
  });
  if (progress) progress->Begin("links (clusters)", candidates.size());
  std::vector<ClusterLink> block;
  for (size_t begin = 0; begin < candidates.size(); begin += kFactorBlock) {
    const size_t end = std::min(candidates.size(), begin + kFactorBlock);
    block.assign(end - begin, ClusterLink{});
    ParallelFor(end - begin, ResolveThreads(threads), [&](size_t k, int) {
      ClusterLink& l = block[k];
      l.a = candidates[begin + k].p;
      l.b = candidates[begin + k].q;
      const Vec3 d = ElementCentre(h, tree, l.b) - ElementCentre(h, tree, l.a);
      const double r2 = Dot(d, d);
      l.direction = Normalized(d);
      const double v = VisibleFraction(h, tree, samples, vis, l.a, l.b);
      const auto factor = [&](uint32_t from, uint32_t to) {
        return IsCluster(from) ? v / (kPi * r2) : v * std::max(0.0, SurfaceFactor(h, tree, from, to));
      };
      l.a_to_b = factor(l.a, l.b);
      l.b_to_a = factor(l.b, l.a);
      if (progress) progress->Advance();
    });
    // Pairs that no ray joins carry nothing.
    for (const ClusterLink& l : block)
      if (l.a_to_b > 0 || l.b_to_a > 0) out.links.push_back(l);
  }
  if (progress) progress->End();
  return out;
}

}  // namespace relight::baker
