// Refinement from the root cluster (Smits, Arvo & Greenberg 1994): a pair of
// elements (clusters or surface nodes, cluster_tree.h) is linked as it is
// when the error of the light it would carry either way is within the
// receiver's bound; otherwise the larger element is split. A cluster with
// itself becomes the pairs of its children. Two surface nodes are left to
// the surface refinement (hierarchy_links.h), which needs them at their own
// level. Refinement cost then grows with the links, not with surfaces², and
// a row of seats far from a wall node gathers its light through one link.
//
// The estimates, for y's light arriving at x:
//   y a surface node:  B_y F_c max(kClusterError, 2 r_x / r)
//   y a cluster:       (sum over y's members of B A) / (pi r²)
//                      x max(kClusterError, 2 (r_x + r_y) / r)
// with F_c the exact factor of y's polygon seen from x's centre (facing it),
// r the centres' distance and r_x, r_y the bounding spheres' radii; only
// for spheres apart. The first factor is the light, the second how much of
// it the link's simplifications can get wrong: the light's change over the
// elements and the six bins' orientation (cluster_tree.h).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "cluster_tree.h"
#include "hierarchy.h"
#include "hierarchy_links.h"
#include "progress.h"
#include "visibility.h"

namespace relight::baker {

struct ClusterLink {
  uint32_t a = 0, b = 0;  // elements, a < b, at least one a cluster
  Vec3 direction{};       // unit, from a's centre to b's
  // What arrives at b from a, on a surface facing a, per unit of a's light,
  // and the reverse (visible fraction included). A cluster's light is its
  // bins weighted by the direction (lm), the factor V / (pi r²); a surface
  // node's light is its exitance (lm/m²), the factor V F_c.
  double a_to_b = 0, b_to_a = 0;
};

struct ClusteredRefinement {
  std::vector<NodePair> node_pairs;  // for the surface refinement
  std::vector<ClusterLink> links;    // sorted by (a, b)
  size_t pairs_visited = 0;
};

// Levels of the cluster walk done on one thread to cut the rest into tasks
// for every thread (about 3^k of them at the top, where clusters split in
// two). Any value gives the same result; 0 walks on one thread.
inline constexpr int kClusterWalkSerialLevels = 10;

// brightness, epsilon: per hierarchy node, as RefineLinks takes them.
ClusteredRefinement RefineClusters(const Hierarchy& h, const ClusterTree& tree,
                                   const NodeSamples& samples, const Visibility& vis,
                                   const std::vector<double>& brightness,
                                   const std::vector<double>& epsilon, int threads,
                                   Progress* progress, int walk_levels = kClusterWalkSerialLevels);

// F_c: the factor of a surface node's polygon seen from a cluster's centre,
// facing it (unoccluded); negative when the centre is behind the node.
double SurfaceFactor(const Hierarchy& h, const ClusterTree& tree, uint32_t node, uint32_t cluster);
// Centre and bounding-sphere radius of an element.
Vec3 ElementCentre(const Hierarchy& h, const ClusterTree& tree, uint32_t element);
double ElementRadius(const Hierarchy& h, const ClusterTree& tree, uint32_t element);

}  // namespace relight::baker
