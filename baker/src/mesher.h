// Meshing: every input surface (a planar convex triangle or quad) becomes a
// grid of patches no larger than the scene's patch size. Vertices are shared
// inside a surface and never across surfaces (each keeps its own normal and
// reflectance). Deterministic: the bake and the reference see the same mesh.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "relight/baker/scene.h"

namespace relight::baker {

struct Patch {
  std::array<uint32_t, 4> vertices{};  // CCW from the lit side; [3] unused for a triangle
  int corner_count = 4;                // 3 or 4
  Vec3 centre{};                       // area centroid, m
  Vec3 normal{};                       // unit, towards the lit side
  double area_m2 = 0;
  double diameter_m = 0;  // longest distance between two corners
  Rgb reflectance{};
  uint32_t surface = 0;
};

// The patch grid of one input surface (the hierarchical solver builds its
// quadtrees over it). Quad: patch (a, b) is first_patch + b * nu + a, grid
// vertex (a, b) is first_vertex + b * (nu + 1) + a. Triangle (nu = nv = k):
// rows j = 0..k-1 of patches up(i, j) then down(i, j), vertices row by row.
struct SurfaceGrid {
  uint32_t first_patch = 0, first_vertex = 0;
  int nu = 0, nv = 0;
  bool triangle = false;
};

struct Mesh {
  std::vector<Vec3> positions;       // per vertex, m
  std::vector<Vec3> vertex_normals;  // unit, the surface's normal
  std::vector<Rgb> vertex_reflectance;
  std::vector<uint32_t> vertex_surface;
  // Patches around vertex v: vertex_patch_ids[vertex_patch_offsets[v] .. [v + 1]).
  std::vector<uint32_t> vertex_patch_offsets;
  std::vector<uint32_t> vertex_patch_ids;
  std::vector<Patch> patches;
  std::vector<uint32_t> triangles;         // 3 per render triangle, CCW from the lit side
  std::vector<uint32_t> triangle_surface;  // input surface per render triangle
  std::vector<Vec3> surface_centroids;     // per input surface, m
  std::vector<SurfaceGrid> surface_grids;  // per input surface
  double scene_diagonal_m = 0;             // bounding-box diagonal (sets ray epsilons)

  size_t vertex_count() const { return positions.size(); }
  size_t patch_count() const { return patches.size(); }
};

// Dense form factors cost 8 n^2 bytes, and the three LU factors as much
// again each: beyond this the dense solver would not fit in memory.
constexpr size_t kMaxDensePatches = 20000;
// The hierarchical solver's memory grows linearly; this only guards against
// a patch size typed in the wrong unit.
constexpr size_t kMaxHierarchicalPatches = 2000000;

// Subdivides every surface: a quad into nu x nv bilinear cells, a triangle
// into k^2 sub-triangles (barycentric grid), each edge at most patch_size_m.
// Throws SceneError for a degenerate or non-planar surface, or for more than
// max_patches patches.
Mesh BuildMesh(const Scene& scene, size_t max_patches = kMaxDensePatches);

// A point on a patch with the fraction of the patch's area it stands for.
struct PatchSample {
  Vec3 point{};
  double weight = 0;  // sums to 1 over a patch's samples
};

// k x k stratified samples (quad: cell midpoints, weighted by the bilinear
// Jacobian; triangle: centroids of k^2 equal sub-triangles).
std::vector<PatchSample> SamplePatch(const Mesh& mesh, const Patch& patch, int k);

}  // namespace relight::baker
