#include "bake_hierarchy.h"

#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "quantise.h"

namespace relight::baker {
namespace {

int32_t ToGradient(double g, uint32_t p, uint32_t q) {
  const double v = std::round(std::ldexp(g, kBakeGradientFracBits));
  if (!(std::abs(v) <= std::numeric_limits<int32_t>::max())) {
    throw std::runtime_error("hierarchy: link " + std::to_string(p) + " - " + std::to_string(q) +
                             ": gradient " + std::to_string(g) +
                             " per metre does not fit Q8.23");
  }
  return static_cast<int32_t>(v);
}

}  // namespace

BakeHierarchy MakeBakeHierarchy(const Mesh& mesh, const Hierarchy& h,
                                const std::vector<HierarchyLink>& links) {
  // The mesher emits a fan of corner_count - 2 render triangles per patch, in patch order.
  std::vector<uint32_t> first_triangle(mesh.patch_count());
  uint32_t triangle = 0;
  for (size_t i = 0; i < mesh.patch_count(); ++i) {
    first_triangle[i] = triangle;
    triangle += static_cast<uint32_t>(mesh.patches[i].corner_count - 2);
  }

  BakeHierarchy out;
  const size_t n = h.nodes.size();
  out.node_surface.resize(n);
  out.node_parent.resize(n);
  out.node_first_child.resize(n);
  out.node_child_count.resize(n);
  out.node_corner_count.resize(n);
  out.node_corners.assign(n * kBakeMaxNodeCorners, kBakeNoIndex);
  out.node_area.resize(n);
  out.node_leaf_triangle.resize(n);
  // Children come after their parents: in reverse, a node's children are done.
  for (size_t k = n; k-- > 0;) {
    const HierarchyNode& node = h.nodes[k];
    if (node.child_count > std::numeric_limits<uint8_t>::max()) {
      throw std::runtime_error("hierarchy: node " + std::to_string(k) + " has " +
                               std::to_string(node.child_count) + " children, at most 255 store");
    }
    out.node_surface[k] = static_cast<uint16_t>(node.surface);
    out.node_parent[k] = node.parent;
    out.node_child_count[k] = static_cast<uint8_t>(node.child_count);
    out.node_corner_count[k] = static_cast<uint8_t>(node.corner_count);
    for (int c = 0; c < node.corner_count; ++c)
      out.node_corners[k * kBakeMaxNodeCorners + static_cast<size_t>(c)] = node.corner_vertices[c];
    if (node.leaf()) {
      out.node_first_child[k] = kBakeNoIndex;
      out.node_leaf_triangle[k] = first_triangle[node.patch];
      out.node_area[k] = static_cast<uint64_t>(std::llround(std::ldexp(node.area_m2, 32)));
    } else {
      out.node_first_child[k] = node.first_child;
      out.node_leaf_triangle[k] = kBakeNoIndex;
      uint64_t area = 0;
      for (uint32_t c = node.first_child; c < node.first_child + node.child_count; ++c)
        area += out.node_area[c];
      out.node_area[k] = area;
    }
  }

  for (const HierarchyLink& l : links) {
    const uint32_t f_pq = ToUq0_32(l.f_pq), f_qp = ToUq0_32(l.f_qp);
    if (f_pq == 0 && f_qp == 0) continue;
    out.link_p.push_back(l.p);
    out.link_q.push_back(l.q);
    out.link_f_pq.push_back(f_pq);
    out.link_f_qp.push_back(f_qp);
    for (int a = 0; a < 2; ++a) {
      out.link_g_pq.push_back(f_pq == 0 ? 0 : ToGradient(l.g_pq[a], l.p, l.q));
      out.link_g_qp.push_back(f_qp == 0 ? 0 : ToGradient(l.g_qp[a], l.p, l.q));
    }
  }
  return out;
}

}  // namespace relight::baker
