#include "grid_links.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "quantise.h"
#include "relight/bake/bake_limits.h"

namespace relight::baker {

void MakeGridLinks(const Mesh& mesh, const Hierarchy& h, const std::vector<Eigen::MatrixXd>& gather,
                   double epsilon, BakeHierarchy* out) {
  const size_t n = h.nodes.size();
  // Each node's leaves (mesh patches), built bottom-up: children come after parents.
  std::vector<std::vector<uint32_t>> leaves(n);
  for (size_t k = n; k-- > 0;) {
    const HierarchyNode& node = h.nodes[k];
    if (node.leaf()) {
      leaves[k].push_back(node.patch);
      continue;
    }
    for (uint32_t c = node.first_child; c < node.first_child + node.child_count; ++c)
      leaves[k].insert(leaves[k].end(), leaves[c].begin(), leaves[c].end());
  }
  out->grid_link_offsets.assign(1, 0);
  out->grid_link_node.clear();
  out->grid_link_f.clear();
  std::vector<double> f(n);
  std::vector<uint32_t> stack, linked;
  for (const Eigen::MatrixXd& g : gather) {
    for (Eigen::Index p = 0; p < g.rows(); ++p) {
      for (size_t k = n; k-- > 0;) {
        const HierarchyNode& node = h.nodes[k];
        double sum = 0;
        if (node.leaf()) {
          sum = g(p, static_cast<Eigen::Index>(node.patch));
        } else {
          for (uint32_t c = node.first_child; c < node.first_child + node.child_count; ++c) sum += f[c];
        }
        f[k] = sum;
      }
      linked.clear();
      for (size_t s = 0; s < h.surface_count(); ++s) {
        if (h.surface_begin[s] == h.surface_begin[s + 1]) continue;  // no tree
        stack.assign(1, h.root(s));
        while (!stack.empty()) {
          const uint32_t k = stack.back();
          stack.pop_back();
          if (!(f[k] > 0)) continue;  // unseen: no light from it
          const HierarchyNode& node = h.nodes[k];
          bool link = node.leaf();
          if (!link) {
            double spread = 0;  // how unevenly the point sees the node's area
            const double per_area = f[k] / node.area_m2;
            for (uint32_t j : leaves[k]) {
              spread += std::abs(g(p, static_cast<Eigen::Index>(j)) - per_area * mesh.patches[j].area_m2);
            }
            link = spread <= epsilon;
          }
          if (link) {
            linked.push_back(k);
          } else {
            for (uint32_t c = node.first_child; c < node.first_child + node.child_count; ++c)
              stack.push_back(c);
          }
        }
      }
      std::sort(linked.begin(), linked.end());
      for (uint32_t k : linked) {
        const uint32_t q = ToUq0_32(f[k]);
        if (q == 0) continue;
        out->grid_link_node.push_back(k);
        out->grid_link_f.push_back(q);
      }
      if (out->grid_link_node.size() > bake_format::kMaxLinks) {
        throw std::runtime_error("grid links: more than " + std::to_string(bake_format::kMaxLinks) +
                                 " (raise --grid-link-epsilon)");
      }
      out->grid_link_offsets.push_back(static_cast<uint32_t>(out->grid_link_node.size()));
    }
  }
}

}  // namespace relight::baker
