// Consistency rules of the stored radiosity hierarchy (sections HIER and
// LINK): every index in range and the trees well formed, so a run-time
// solve can walk nodes and links without a single bounds check of its own.
#include <cstddef>
#include <vector>

#include "relight/bake/bake_check.h"
#include "bake_format.h"
#include "relight/base/status.h"

namespace relight::bake_format {
namespace {

using ull = unsigned long long;

std::string NodeError(size_t node, const std::string& what) {
  return StrFormat("node %llu: %s", static_cast<ull>(node), what.c_str());
}

std::string LinkError(size_t link, const std::string& what) {
  return StrFormat("link %llu: %s", static_cast<ull>(link), what.c_str());
}

// An array of a node (link) record and its length.
struct ArrayLength {
  const char* what;
  size_t have, per_item;
};

// Every array holds per_item values for each of `items` nodes (links).
template <size_t N>
std::string CheckLengths(const ArrayLength (&arrays)[N], size_t items, const char* item_name) {
  for (const ArrayLength& a : arrays) {
    if (a.have != a.per_item * items) {
      const std::string how = a.per_item == 1 ? std::string(item_name)
                                              : StrFormat("%llu x %s",
                                                          static_cast<ull>(a.per_item), item_name);
      return CountMismatch(a.what, a.have, how.c_str(), a.per_item * items);
    }
  }
  return "";
}

// 3 to 6 distinct mesh vertices, unused slots kBakeNoIndex.
std::string CheckCorners(const BakeHierarchy& h, size_t k, uint64_t vertices) {
  const unsigned count = h.node_corner_count[k];
  if (count < kMinNodeCorners || count > static_cast<unsigned>(kBakeMaxNodeCorners)) {
    return StrFormat("%u corners, expected %u to %d", count, kMinNodeCorners, kBakeMaxNodeCorners);
  }
  const uint32_t* c = &h.node_corners[k * kBakeMaxNodeCorners];
  for (unsigned j = 0; j < static_cast<unsigned>(kBakeMaxNodeCorners); ++j) {
    if (j >= count) {
      if (c[j] != kBakeNoIndex) {
        return StrFormat("unused corner slot %u holds %u, not 0xFFFFFFFF", j, c[j]);
      }
      continue;
    }
    if (c[j] >= vertices) {
      return StrFormat("corner %u: vertex index %u >= vertex count %llu", j, c[j],
                       static_cast<ull>(vertices));
    }
    for (unsigned i = 0; i < j; ++i) {
      if (c[i] == c[j]) return StrFormat("corners %u and %u are both vertex %u", i, j, c[j]);
    }
  }
  return "";
}

// A leaf's render triangles: the fan of its corners, on its surface, in no other leaf.
std::string CheckLeafTriangles(const BakeHierarchy& h, size_t k, const BakeMesh& mesh,
                               std::vector<uint8_t>* covered) {
  const uint64_t t = mesh.triangle_count();
  const uint32_t first = h.node_leaf_triangle[k];
  const uint32_t count = h.node_corner_count[k] - 2u;
  if (first >= t || count > t - first) {
    return StrFormat("leaf triangles [%u, %llu) run past the triangle count %llu", first,
                     static_cast<ull>(uint64_t{first} + count), static_cast<ull>(t));
  }
  const uint32_t* c = &h.node_corners[k * kBakeMaxNodeCorners];
  for (uint32_t j = 0; j < count; ++j) {
    const uint32_t tri = first + j;
    const uint32_t* v = &mesh.triangles[3 * size_t{tri}];
    if (v[0] != c[0] || v[1] != c[j + 1] || v[2] != c[j + 2]) {
      return StrFormat("triangle %u is (%u, %u, %u), not (%u, %u, %u) of the fan of the node's "
                       "corners",
                       tri, v[0], v[1], v[2], c[0], c[j + 1], c[j + 2]);
    }
    if (mesh.triangle_surface[tri] != h.node_surface[k]) {
      return StrFormat("triangle %u is on surface %u, the node on surface %u", tri,
                       mesh.triangle_surface[tri], h.node_surface[k]);
    }
    if ((*covered)[tri] != 0) return StrFormat("triangle %u is in another leaf too", tri);
    (*covered)[tri] = 1;
  }
  return "";
}

}  // namespace

std::string CheckHierarchyNodes(const BakeHierarchy& h, const BakeMesh& mesh) {
  const ArrayLength arrays[] = {{"node_parent", h.node_parent.size(), 1},
                                {"node_first_child", h.node_first_child.size(), 1},
                                {"node_child_count", h.node_child_count.size(), 1},
                                {"node_corner_count", h.node_corner_count.size(), 1},
                                {"node_corners", h.node_corners.size(), kBakeMaxNodeCorners},
                                {"node_area", h.node_area.size(), 1},
                                {"node_leaf_triangle", h.node_leaf_triangle.size(), 1}};
  std::string e = CheckLengths(arrays, h.node_surface.size(), "nodes");
  if (!e.empty()) return e;
  const uint64_t n = h.node_surface.size();
  const uint64_t t = mesh.triangle_count(), v = mesh.vertex_count();
  const uint64_t s = mesh.surface_names.size();
  if (n == 0) return "no nodes";
  if (n + 1 > 2 * t) {
    return StrFormat("%llu nodes, but %llu triangles allow at most 2 x triangles - 1",
                     static_cast<ull>(n), static_cast<ull>(t));
  }
  std::vector<uint8_t> covered(static_cast<size_t>(t), 0);
  // Breadth first per surface: the children of a surface's nodes, taken in
  // node order, tile the nodes after its root. Every other node lies in its
  // parent's range and every child names that parent, so the tiling ends
  // exactly where the next surface's root begins.
  uint64_t root = 0, next_child = 0;
  for (uint64_t k = 0; k < n; ++k) {
    const uint32_t surface = h.node_surface[k];
    const uint32_t parent = h.node_parent[k];
    if (surface >= s) {
      return NodeError(k, StrFormat("surface %u >= surface count %llu", surface,
                                    static_cast<ull>(s)));
    }
    if (k == 0 || surface != h.node_surface[k - 1]) {
      if (k > 0 && surface < h.node_surface[k - 1]) {
        return NodeError(k, StrFormat("surface %u comes after surface %u (nodes go surface by "
                                      "surface in order)",
                                      surface, h.node_surface[k - 1]));
      }
      if (parent != kBakeNoIndex) {
        return NodeError(k, StrFormat("the first node of surface %u has parent %u (it must be "
                                      "the root)",
                                      surface, parent));
      }
      root = k;
      next_child = k + 1;
    } else if (parent == kBakeNoIndex) {
      return NodeError(k, StrFormat("a second root on surface %u", surface));
    } else if (parent < root || parent >= k) {
      return NodeError(k, StrFormat("parent %u is not an earlier node of surface %u", parent,
                                    surface));
    } else if (k < h.node_first_child[parent] ||
               k - h.node_first_child[parent] >= h.node_child_count[parent]) {
      return NodeError(k, StrFormat("is not among the children of its parent %u", parent));
    }
    e = CheckCorners(h, static_cast<size_t>(k), v);
    if (!e.empty()) return NodeError(k, e);
    const uint64_t area = h.node_area[k];
    if (area == 0 || area > kMaxNodeAreaRaw) {
      return NodeError(k, StrFormat("area %llu (Q32.32 m^2) is outside [1, 2^56]",
                                    static_cast<ull>(area)));
    }
    const uint32_t first = h.node_first_child[k];
    const uint32_t children = h.node_child_count[k];
    if (children == 0) {
      if (first != kBakeNoIndex) {
        return NodeError(k, StrFormat("a leaf with first child %u (0xFFFFFFFF expected)", first));
      }
      e = CheckLeafTriangles(h, static_cast<size_t>(k), mesh, &covered);
      if (!e.empty()) return NodeError(k, e);
      continue;
    }
    if (children < kMinChildren) {
      return NodeError(k, StrFormat("%u child; an inner node has at least %u", children,
                                    kMinChildren));
    }
    if (h.node_leaf_triangle[k] != kBakeNoIndex) {
      return NodeError(k, StrFormat("an inner node with leaf triangle %u (0xFFFFFFFF expected)",
                                    h.node_leaf_triangle[k]));
    }
    if (first != next_child) {
      return NodeError(k, StrFormat("children start at node %u, expected %llu (breadth first, "
                                    "contiguous)",
                                    first, static_cast<ull>(next_child)));
    }
    if (children > n - first) {
      return NodeError(k, StrFormat("children [%u, %llu) run past the node count %llu", first,
                                    static_cast<ull>(uint64_t{first} + children),
                                    static_cast<ull>(n)));
    }
    next_child += children;
    UInt128 sum = 0;
    for (uint32_t c = first; c < first + children; ++c) {
      if (h.node_parent[c] != k) {
        return NodeError(k, StrFormat("child %u names node %u as its parent", c,
                                      h.node_parent[c]));
      }
      sum += h.node_area[c];
    }
    if (sum != area) {
      return NodeError(k, StrFormat("area %llu (Q32.32 m^2) is not the sum of its children's",
                                    static_cast<ull>(area)));
    }
  }
  for (size_t tri = 0; tri < covered.size(); ++tri) {
    if (covered[tri] == 0) {
      return StrFormat("triangle %llu is in no leaf", static_cast<ull>(tri));
    }
  }
  return "";
}

std::string CheckHierarchyLinks(const BakeHierarchy& h) {
  const size_t links = h.link_p.size();
  if (links > kMaxLinks) {
    return StrFormat("%llu links exceed the limit %u", static_cast<ull>(links), kMaxLinks);
  }
  const ArrayLength arrays[] = {{"link_q", h.link_q.size(), 1},
                                {"link_f_pq", h.link_f_pq.size(), 1},
                                {"link_f_qp", h.link_f_qp.size(), 1},
                                {"link_g_pq", h.link_g_pq.size(), 2},
                                {"link_g_qp", h.link_g_qp.size(), 2}};
  const std::string e = CheckLengths(arrays, links, "links");
  if (!e.empty()) return e;
  const uint32_t n = h.node_count();
  for (size_t i = 0; i < links; ++i) {
    const uint32_t p = h.link_p[i], q = h.link_q[i];
    if (p >= n || q >= n) {
      return LinkError(i, StrFormat("node %u >= node count %u", p >= n ? p : q, n));
    }
    if (p >= q) return LinkError(i, StrFormat("p %u is not below q %u", p, q));
    if (i > 0 && (p < h.link_p[i - 1] || (p == h.link_p[i - 1] && q <= h.link_q[i - 1]))) {
      return LinkError(i, StrFormat("(%u, %u) does not come after (%u, %u) (sorted by p, then q, "
                                    "no repeats)",
                                    p, q, h.link_p[i - 1], h.link_q[i - 1]));
    }
    if (h.node_surface[p] == h.node_surface[q]) {
      return LinkError(i, StrFormat("nodes %u and %u are both on surface %u", p, q,
                                    h.node_surface[p]));
    }
    if (h.link_f_pq[i] == 0 && h.link_f_qp[i] == 0) return LinkError(i, "both factors are 0");
    // The gradient over the receiving node: none for a leaf or a zero factor.
    const struct {
      uint32_t node, f;
      const int32_t* g;
    } ends[] = {{p, h.link_f_pq[i], &h.link_g_pq[2 * i]}, {q, h.link_f_qp[i], &h.link_g_qp[2 * i]}};
    for (const auto& end : ends) {
      if ((end.g[0] != 0 || end.g[1] != 0) && (h.leaf(end.node) || end.f == 0)) {
        return LinkError(i, StrFormat("gradient (%d, %d) over node %u, which %s", end.g[0],
                                      end.g[1], end.node,
                                      h.leaf(end.node) ? "is a leaf" : "gets a zero factor"));
      }
    }
  }
  // Each factor is UQ0.32, so in [0, 1] by its format (2^32 - 1 stands for
  // 1). What a receiver gathers matters: a leaf's irradiance sums f x B over
  // its own links and its ancestors' (pushed down), and that sum F is a form
  // factor sum, 1 in a closed room; the baker's sampled estimates reach
  // ~1.06, so F <= 2 is required. Then a gather in the emitter solve
  // (surface_emitter_solve.cc) sums at most 2^33 (F in UQ0.32) x 2^63 (B,
  // int64) = 2^96 into Int128, whatever B is: safe by 2^31. Unchecked, F
  // could be 2^28 links x 1 and B grow by that factor every sweep.
  constexpr uint64_t kMaxGatherSumRaw = uint64_t{1} << 33;
  std::vector<uint64_t> gathered(n, 0);  // own links first, <= 2^28 x 2^32
  for (size_t i = 0; i < links; ++i) {
    gathered[h.link_p[i]] += h.link_f_pq[i];
    gathered[h.link_q[i]] += h.link_f_qp[i];
  }
  for (uint32_t k = 0; k < n; ++k) {  // parents come before children
    if (h.node_parent[k] != kBakeNoIndex && gathered[k] <= kMaxGatherSumRaw) {
      gathered[k] += gathered[h.node_parent[k]];  // both <= the bound: no wrap
    }
    if (gathered[k] > kMaxGatherSumRaw) {
      // Printed without floating point (the runtime has none): whole.millionths.
      const uint64_t millionths = ((gathered[k] & 0xFFFFFFFFu) * 1000000u) >> 32;
      return NodeError(k, StrFormat("its links and its ancestors' gather form factors summing "
                                    "to %llu.%06llu, more than 2 (UQ0.32 raw %llu)",
                                    static_cast<ull>(gathered[k] >> 32),
                                    static_cast<ull>(millionths), static_cast<ull>(gathered[k])));
    }
  }
  return "";
}

}  // namespace relight::bake_format
