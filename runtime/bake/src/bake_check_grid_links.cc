// CheckGridLinks (bake_check.h): the GLNK links against nodes that passed
// CheckHierarchyNodes.
#include <cstdint>
#include <string>

#include "relight/bake/bake_check.h"
#include "relight/bake/bake_limits.h"

namespace relight::bake_format {

std::string CheckGridLinks(const BakeHierarchy& h, uint64_t grid_points) {
  using ull = unsigned long long;
  if (!h.has_grid_links()) return "";
  if (h.grid_link_offsets.size() != grid_points + 1) {
    return CountMismatch("grid_link_offsets", h.grid_link_offsets.size(), "grid points + 1",
                         grid_points + 1);
  }
  const size_t links = h.grid_link_node.size();
  if (links > kMaxLinks) {
    return StrFormat("%llu grid links exceed the limit %u", static_cast<ull>(links), kMaxLinks);
  }
  if (h.grid_link_f.size() != links) {
    return CountMismatch("grid_link_f", h.grid_link_f.size(), "grid links", links);
  }
  if (h.grid_link_offsets[0] != 0 || h.grid_link_offsets[grid_points] != links) {
    return StrFormat("grid link offsets run from %u to %u, expected 0 to the link count %llu",
                     h.grid_link_offsets[0], h.grid_link_offsets[grid_points], static_cast<ull>(links));
  }
  const uint32_t n = h.node_count();
  // As for the node links (CheckHierarchyLinks): a point's factors are a
  // form factor sum, 1 for a point facing a closed room; at most 2 is
  // required, so the engine's gather (Int128, emitter_grids.cc) sums at
  // most 2^33 x 2^63 whatever the exitance.
  constexpr uint64_t kMaxGatherSumRaw = uint64_t{1} << 33;
  for (uint64_t p = 0; p < grid_points; ++p) {
    const uint32_t e0 = h.grid_link_offsets[p], e1 = h.grid_link_offsets[p + 1];
    if (e1 < e0 || e1 > links) {
      return StrFormat("grid point %llu: links [%u, %u) are not a range within [0, %llu)",
                       static_cast<ull>(p), e0, e1, static_cast<ull>(links));
    }
    uint64_t sum = 0;
    for (uint32_t e = e0; e < e1; ++e) {
      const uint32_t node = h.grid_link_node[e];
      if (node >= n) {
        return StrFormat("grid point %llu, link %u: node %u >= node count %u", static_cast<ull>(p), e,
                         node, n);
      }
      if (e > e0 && node <= h.grid_link_node[e - 1]) {
        return StrFormat("grid point %llu, link %u: node %u does not come after %u (ascending, no "
                         "repeats)",
                         static_cast<ull>(p), e, node, h.grid_link_node[e - 1]);
      }
      sum += h.grid_link_f[e];  // <= 2^33 + 2^32 before the test below fires
      if (sum > kMaxGatherSumRaw) {
        return StrFormat("grid point %llu: its link factors sum to more than 2 (UQ0.32 raw %llu)",
                         static_cast<ull>(p), static_cast<ull>(sum));
      }
    }
  }
  return "";
}

}  // namespace relight::bake_format
