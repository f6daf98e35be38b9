// Volume clusters above the surfaces' quadtrees (Smits, Arvo & Greenberg
// 1994, "A clustering algorithm for radiosity in complex environments"): a
// binary tree over the input surfaces, split at the median of the longest
// axis, so that refinement can start from one pair (the root cluster with
// itself) instead of every pair of surfaces. A row of seats far from the
// ceiling then exchanges its light through one link, not one per seat face.
//
// An element of the refinement is either a cluster or a node of a surface's
// quadtree (hierarchy.h); Element() tells them apart by the top bit.
//
// A cluster's light is direction dependent: its members face many ways. It
// is carried in six bins, one per axis direction (+x, -x, +y, -y, +z, -z):
// leaving, a member of exitance B, area A and normal n adds B A max(0, +-n_i)
// to bin (+-, i); arriving from direction u, irradiance E adds E |u_i| to the
// bin of u_i's sign, and a member of normal n receives sum_i |n_i| bin(sign
// n_i, i). Both are exact for members square to the axes and within a factor
// of sqrt(3) otherwise, never negative; the refinement only links clusters
// where the whole transfer is below the error bound (cluster_links.h).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "hierarchy.h"

namespace relight::baker {

constexpr uint32_t kClusterBit = 0x80000000u;
inline bool IsCluster(uint32_t element) { return (element & kClusterBit) != 0; }
inline uint32_t ClusterElement(uint32_t cluster) { return cluster | kClusterBit; }
inline uint32_t ClusterIndex(uint32_t element) { return element & ~kClusterBit; }

constexpr int kClusterBins = 6;
// Bin of axis `axis` (0..2) in the direction of the sign of `component`.
inline int ClusterBin(int axis, double component) { return 2 * axis + (component < 0 ? 1 : 0); }

// Points a cluster's visibility rays start from: spread over its members.
constexpr int kClusterSamples = 16;

struct ClusterPoint {
  Vec3 point{}, normal{};
};

struct Cluster {
  Vec3 lo{}, hi{};                              // bounding box of the members' corners, m
  Vec3 centre{};                                // area centroid of the members, m
  double radius_m = 0;                          // a sphere about centre holding every member
  double area_m2 = 0;                           // members' total area
  std::array<uint32_t, 2> children{};           // elements: clusters or surface roots
  uint32_t first_member = 0, member_count = 0;  // into ClusterTree::members
  std::array<ClusterPoint, kClusterSamples> samples{};
};

struct ClusterTree {
  // Parents before children; clusters[0] is the root (all surfaces).
  std::vector<Cluster> clusters;
  std::vector<uint32_t> members;  // surface indices, each cluster's a contiguous run
  // Per surface, the bins' weights of its root: max(0, +-n_i) per bin.
  std::vector<std::array<double, kClusterBins>> surface_bins;

  bool empty() const { return clusters.empty(); }
  // The element holding every surface (a lone surface's root with one surface).
  uint32_t root_element(const Hierarchy& h) const {
    return clusters.empty() ? h.root(0) : ClusterElement(0);
  }
};

// Empty for fewer than two surfaces.
ClusterTree BuildClusterTree(const Hierarchy& h);

}  // namespace relight::baker
