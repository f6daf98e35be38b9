// Float64 references for the run-time emitter tests: convex polygon clipping
// in a surface's plane, node polygons read from the bake, emitter shapes.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "plane_polygon.h"
#include "radiosity_vec.h"
#include "relight/bake/bake.h"
#include "relight/baker/scene.h"
#include "relight/engine/engine.h"
#include "relight/engine/surface_emitter.h"

namespace relight::testing {

using baker::Vec3;
using baker::Vec2;

using baker::ClipConvex;
using baker::SignedArea;

// A plane seen along its normal's largest axis: area ratios within the plane
// are those of the projection, and points a rounding off the plane do not
// move sideways.
struct AxisPlane {
  int a = 0, b = 1;
  explicit AxisPlane(const Vec3& normal) {
    int drop = 0;
    for (int i = 1; i < 3; ++i)
      if (std::abs(normal[i]) > std::abs(normal[drop])) drop = i;
    a = (drop + 1) % 3;
    b = (drop + 2) % 3;
  }
  // Counter-clockwise in the projection.
  std::vector<Vec2> Polygon(const std::vector<Vec3>& corners) const {
    std::vector<Vec2> out;
    for (const Vec3& c : corners) out.push_back({c[a], c[b]});
    if (SignedArea(out) < 0) std::reverse(out.begin(), out.end());
    return out;
  }
};

inline double Area3(const std::vector<Vec3>& p) {
  using namespace baker::radiosity_vec;
  Vec3 sum{0, 0, 0};
  for (size_t i = 1; i + 1 < p.size(); ++i) sum += Cross(p[i] - p[0], p[i + 1] - p[0]);
  return 0.5 * Length(sum);
}

inline Vec3 BakeVertex(const BakeMesh& mesh, uint32_t v) {
  const int32_t* p = &mesh.positions[3 * size_t{v}];
  return {p[0] / 65536.0, p[1] / 65536.0, p[2] / 65536.0};
}

inline std::vector<Vec3> NodeCorners(const Bake& bake, uint32_t node) {
  const BakeHierarchy& h = *bake.hierarchy;
  std::vector<Vec3> out;
  for (int k = 0; k < h.node_corner_count[node]; ++k)
    out.push_back(BakeVertex(bake.mesh, h.node_corners[size_t{node} * kBakeMaxNodeCorners + k]));
  return out;
}

inline uint32_t SurfaceRoot(const Bake& bake, const std::string& name) {
  const BakeHierarchy& h = *bake.hierarchy;
  for (uint32_t k = 0; k < h.node_count(); ++k) {
    if (h.node_parent[k] == kBakeNoIndex && bake.mesh.surface_names[h.node_surface[k]] == name)
      return k;
  }
  return kBakeNoIndex;
}

inline SurfaceEmitterShape MakeShape(const std::string& surface, const std::vector<Vec3>& corners) {
  SurfaceEmitterShape shape;
  shape.surface = surface;
  shape.corner_count = static_cast<int>(corners.size());
  for (size_t k = 0; k < corners.size() && k < kMaxSurfaceEmitterCorners; ++k)
    for (int i = 0; i < 3; ++i)
      shape.corners_q16[k][i] = static_cast<int32_t>(std::llround(corners[k][i] * 65536.0));
  return shape;
}

// Update(), then Update() again until no emitter is left a quick answer to
// settle (EngineOptions::emitter_quick_changes): the state a still scene
// reaches one idle frame later.
inline void UpdateSettled(Engine* engine) {
  engine->Update();
  for (int i = 0; i < 4 && !engine->emitters_settled(); ++i) engine->Update();
}

}  // namespace relight::testing
