// The patch hierarchy of hierarchical radiosity (Hanrahan, Salzman & Aupperle
// 1991): one quadtree per input surface whose leaves are exactly the mesh
// patches, so everything downstream of the solve (vertex averaging, grid
// gathers, direct light) sees the same patches as with the dense solver.
//
// A node is a convex polygon cut from its surface's patch grid along grid
// lines: a rectangle of cells on a quad surface; on a triangle surface a
// region bounded by lines of the three grid directions (i, j, i + j), at most
// a hexagon. Each node has 2-4 children; node areas are exact sums of their
// leaves' areas. Chandran & Srivastava's run-time emitters need the same
// structure (docs/hierarchy.md).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "form_factors.h"
#include "mesher.h"

namespace relight::baker {

constexpr uint32_t kNoNode = 0xffffffffu;
constexpr int kMaxNodeCorners = 6;

struct HierarchyNode {
  std::array<Vec3, kMaxNodeCorners> corners{};  // convex, CCW from the lit side
  std::array<uint32_t, kMaxNodeCorners> corner_vertices{};  // the mesh vertices at corners
  int corner_count = 0;
  Vec3 centre{};  // area centroid, m
  Vec3 normal{};  // unit, the surface's
  double area_m2 = 0;
  double diameter_m = 0;  // longest distance between two corners
  uint32_t surface = 0;
  uint32_t patch = kNoNode;  // leaves: the mesh patch
  uint32_t parent = kNoNode;
  uint32_t first_child = 0;  // children are nodes [first_child, first_child + child_count)
  uint32_t child_count = 0;
  uint32_t depth = 0;  // 0 at a surface's root

  bool leaf() const { return child_count == 0; }
};

// An orthonormal frame in a surface's plane (u along its first edge): links
// describe how their light varies over a receiving node as a gradient in it.
struct SurfaceFrame {
  Vec3 origin{}, u{}, v{};
};

struct Hierarchy {
  // Breadth first per surface: surface s owns nodes [surface_begin[s],
  // surface_begin[s + 1]), its root first; parents come before children.
  std::vector<HierarchyNode> nodes;
  std::vector<uint32_t> surface_begin;  // surfaces + 1 entries
  std::vector<uint32_t> leaf_of_patch;  // mesh patch -> leaf node
  std::vector<SurfaceFrame> frames;     // per surface

  size_t surface_count() const { return surface_begin.empty() ? 0 : surface_begin.size() - 1; }
  uint32_t root(size_t surface) const { return surface_begin[surface]; }
  // (u, v) of a point in its surface's frame, m.
  std::array<double, 2> PlaneCoords(uint32_t surface, const Vec3& x) const;
};

Hierarchy BuildHierarchy(const Mesh& mesh);

// Stratified points on a node for form-factor quadrature and visibility:
// the mesh patch's own sets for leaves (so leaf links equal the dense
// matrix's entries), computed from the node's polygon otherwise.
class NodeSamples {
 public:
  NodeSamples(const Hierarchy& hierarchy, const PatchSampleSets& patch_samples);
  const std::vector<PatchSample>& coarse(uint32_t node) const;
  const std::vector<PatchSample>& fine(uint32_t node) const;

 private:
  const Hierarchy& hierarchy_;
  const PatchSampleSets& patch_samples_;
  std::vector<std::vector<PatchSample>> coarse_, fine_;  // internal nodes only
};

// Quadrature points on a convex polygon: a quad gets k x k bilinear cell
// midpoints weighted by the Jacobian (as SamplePatch); other polygons a fan
// of triangles, each split into m^2 congruent sub-triangles (their centroids).
std::vector<PatchSample> SamplePolygon(const Vec3* corners, int count, bool fine);

}  // namespace relight::baker
