#include "cluster_tree.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "radiosity_vec.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;

// Point k of a member's spread: its centre, then halfway to each corner in
// turn (inside, since the node is convex).
Vec3 MemberPoint(const HierarchyNode& root, int k) {
  if (k == 0 || root.corner_count == 0) return root.centre;
  const Vec3& corner = root.corners[static_cast<size_t>((k - 1) % root.corner_count)];
  return root.centre + 0.5 * (corner - root.centre);
}

class TreeBuilder {
 public:
  TreeBuilder(const Hierarchy& h, ClusterTree* tree) : h_(h), tree_(tree) {}

  // Fills cluster `index` from members [begin, end) and recurses; children
  // are appended after their parent.
  void Build(uint32_t index, uint32_t begin, uint32_t end) {
    Describe(index, begin, end);
    // Median of the longest axis of the members' centres; ties by surface
    // index, so the tree does not depend on the sort's implementation.
    Vec3 lo{}, hi{};
    lo.fill(std::numeric_limits<double>::max());
    hi.fill(-std::numeric_limits<double>::max());
    for (uint32_t k = begin; k < end; ++k) {
      const Vec3& c = h_.nodes[h_.root(tree_->members[k])].centre;
      for (int i = 0; i < 3; ++i) {
        lo[i] = std::min(lo[i], c[i]);
        hi[i] = std::max(hi[i], c[i]);
      }
    }
    int axis = 0;
    for (int i = 1; i < 3; ++i)
      if (hi[i] - lo[i] > hi[axis] - lo[axis]) axis = i;
    const uint32_t mid = begin + (end - begin) / 2;
    auto* m = tree_->members.data();
    std::nth_element(m + begin, m + mid, m + end, [&](uint32_t a, uint32_t b) {
      const double ca = h_.nodes[h_.root(a)].centre[axis];
      const double cb = h_.nodes[h_.root(b)].centre[axis];
      return ca != cb ? ca < cb : a < b;
    });
    const std::array<std::array<uint32_t, 2>, 2> halves{{{begin, mid}, {mid, end}}};
    for (int c = 0; c < 2; ++c) {
      const auto [b, e] = halves[static_cast<size_t>(c)];
      if (e - b == 1) {
        tree_->clusters[index].children[static_cast<size_t>(c)] = h_.root(tree_->members[b]);
        continue;
      }
      const auto child = static_cast<uint32_t>(tree_->clusters.size());
      tree_->clusters.emplace_back();
      tree_->clusters[index].children[static_cast<size_t>(c)] = ClusterElement(child);
      Build(child, b, e);
    }
  }

 private:
  void Describe(uint32_t index, uint32_t begin, uint32_t end) {
    Cluster& c = tree_->clusters[index];
    c.first_member = begin;
    c.member_count = end - begin;
    c.lo.fill(std::numeric_limits<double>::max());
    c.hi.fill(-std::numeric_limits<double>::max());
    Vec3 moment{0, 0, 0};
    for (uint32_t k = begin; k < end; ++k) {
      const HierarchyNode& root = h_.nodes[h_.root(tree_->members[k])];
      c.area_m2 += root.area_m2;
      moment += root.area_m2 * root.centre;
      for (int j = 0; j < root.corner_count; ++j) {
        for (int i = 0; i < 3; ++i) {
          c.lo[i] = std::min(c.lo[i], root.corners[static_cast<size_t>(j)][i]);
          c.hi[i] = std::max(c.hi[i], root.corners[static_cast<size_t>(j)][i]);
        }
      }
    }
    c.centre = c.area_m2 > 0 ? (1.0 / c.area_m2) * moment : 0.5 * (c.lo + c.hi);
    // The farthest box corner bounds every member's distance from the centre.
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3 x{(corner & 1) ? c.hi[0] : c.lo[0], (corner & 2) ? c.hi[1] : c.lo[1],
                   (corner & 4) ? c.hi[2] : c.lo[2]};
      c.radius_m = std::max(c.radius_m, Length(x - c.centre));
    }
    // Members spread over the run; with fewer members than samples each
    // gives several points.
    const uint32_t count = end - begin;
    uint32_t previous = 0, repeat = 0;
    for (uint32_t k = 0; k < kClusterSamples; ++k) {
      const uint32_t at = begin + (k * count) / kClusterSamples;
      repeat = (k > 0 && at == previous) ? repeat + 1 : 0;
      previous = at;
      const HierarchyNode& root = h_.nodes[h_.root(tree_->members[at])];
      c.samples[k] = {MemberPoint(root, static_cast<int>(repeat)), root.normal};
    }
  }

  const Hierarchy& h_;
  ClusterTree* tree_;
};

}  // namespace

ClusterTree BuildClusterTree(const Hierarchy& h) {
  ClusterTree tree;
  const size_t surfaces = h.surface_count();
  tree.surface_bins.resize(surfaces);
  for (size_t s = 0; s < surfaces; ++s) {
    const Vec3& n = h.nodes[h.root(s)].normal;
    auto& bins = tree.surface_bins[s];
    bins.fill(0);
    for (int i = 0; i < 3; ++i) bins[static_cast<size_t>(ClusterBin(i, n[i]))] = std::abs(n[i]);
  }
  if (surfaces < 2) return tree;
  tree.members.resize(surfaces);
  for (size_t s = 0; s < surfaces; ++s) tree.members[s] = static_cast<uint32_t>(s);
  tree.clusters.reserve(surfaces - 1);
  tree.clusters.emplace_back();
  TreeBuilder(h, &tree).Build(0, 0, static_cast<uint32_t>(surfaces));
  return tree;
}

}  // namespace relight::baker
