#include "bake_exercise.h"

#include <cstdint>
#include <utility>

#include "relight/base/fixed.h"
#include "relight/engine/engine.h"
#include "relight/engine/surface_emitter.h"

namespace relight::fuzz {
namespace {

// The first root node's polygon shrunk by half about its corner mean: convex
// and on its surface's plane whenever the bake's own polygon is.
bool EmitterOnFirstRoot(const Bake& bake, SurfaceEmitterShape* shape) {
  const BakeHierarchy& h = *bake.hierarchy;
  if (h.node_count() == 0) return false;
  const uint32_t surface = h.node_surface[0];
  if (surface >= bake.mesh.surface_names.size()) return false;
  const int corners = h.node_corner_count[0];
  if (corners < kMinSurfaceEmitterCorners || corners > kMaxSurfaceEmitterCorners) return false;
  int64_t mean[3] = {0, 0, 0};
  for (int k = 0; k < corners; ++k) {
    const uint32_t v = h.node_corners[static_cast<size_t>(k)];
    for (int a = 0; a < 3; ++a) mean[a] += bake.mesh.positions[3 * static_cast<size_t>(v) + a];
  }
  shape->surface = bake.mesh.surface_names[surface];
  shape->corner_count = corners;
  for (int k = 0; k < corners; ++k) {
    const uint32_t v = h.node_corners[static_cast<size_t>(k)];
    for (int a = 0; a < 3; ++a) {
      const int64_t c = mean[a] / corners;
      shape->corners_q16[k][a] = static_cast<int32_t>(c + (bake.mesh.positions[3 * static_cast<size_t>(v) + a] - c) / 2);
    }
  }
  return true;
}

}  // namespace

void ExerciseBake(Bake bake) {
  const bool hierarchical = bake.hierarchy.has_value();
  SurfaceEmitterShape shape;
  const bool emitter = hierarchical && EmitterOnFirstRoot(bake, &shape);
  Engine engine;
  if (!engine.Open(std::move(bake)).ok()) return;
  engine.Update();
  if (engine.luminaire_count() > 0) {
    (void)engine.SetDimmer(0, Q1_15::FromRaw(16384));
    (void)engine.SetPanTilt16(0, 40000, 20000);
  }
  if (emitter) {
    const LightQ12 warm[3] = {LightQ12::FromRaw(300 << 12), LightQ12::FromRaw(220 << 12),
                              LightQ12::FromRaw(150 << 12)};
    (void)engine.SetSurfaceEmitter(0, shape, warm);
  }
  engine.Update();
}

}  // namespace relight::fuzz
