// relightd's run-time emitters: a patch's [[emitter]] entries
// (relight/hal/patch.h) bound to the engine's surface-emitter slots
// (emitter i -> slot i; engine.h SetSurfaceEmitter). Inputs move an
// emitter's levels (dimmer, r, g, b, x, y, size; relight/base/param.h) as
// they move a fixture's; this is where they become a polygon on the surface
// and a luminance.
//
// Set() only records a level. Flush(), once per frame after the fader,
// makes at most one engine call per emitter that changed: many changes in a
// frame cost one clip and one solve, not one each (a move costs a solve):
//   dimmer 0            RemoveSurfaceEmitter (its light is gone, bit for bit)
//   x, y or size moved  SetSurfaceEmitter    (clip now, solve at Update)
//   dimmer, colour      SetSurfaceEmitterLuminance (a rescale)
//
// Geometry: the surface's plane has axes u and v in metres. u runs along
// world x projected onto the plane (world y on a wall facing x), v along
// world z (world y on a floor or ceiling). x offsets the shape along u by
// x_range_m[0] + x (x_range_m[1] - x_range_m[0]), y along v likewise, and
// size scales it about its centre by size_range[0] + size (...). The
// corners are integer Q16.16 from axes found once, at Bind.
//
// No allocation after Bind (the shapes and their surface names are built
// there; the engine's error text aside). Thread safety: none.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "relight/base/param.h"
#include "relight/base/status.h"
#include "relight/engine/engine.h"
#include "relight/engine/surface_emitter.h"
#include "relight/hal/patch.h"

namespace relight::control {

static_assert(hal::kMaxPatchEmitters == kMaxSurfaceEmitters, "the patch allows what the engine holds");
static_assert(hal::kMaxPatchEmitterCorners == kMaxSurfaceEmitterCorners, "the patch allows what the engine holds");

class EmitterBinding {
 public:
  // Clears the engine's emitter slots, finds each emitter's plane axes from
  // its surface in the bake, and checks the shape at the four corners of its
  // x, y range at its largest size (each placed, then removed): if those lie
  // on the surface, every position and size between does (the surface and
  // the shape are convex). Errors "WHERE:LINE: emitter 'name': why": an
  // unknown surface, a bake without a hierarchy, a shape off the surface.
  Status Bind(Engine* engine, const std::vector<hal::EmitterPatch>& emitters, const std::string& where);

  int count() const { return static_cast<int>(bound_.size()); }
  // Records emitter `index`'s new level (Q1.15, the dimmer after its curve).
  // False for an index out of range or a parameter emitters lack (pan, tilt,
  // roll, zoom).
  bool Set(int index, Param param, int32_t level_q15);
  // Hands every changed emitter to the engine (one call each). Returns how
  // many calls failed (the first message in *error when given).
  int Flush(Status* error);

  // Emitter `index` as last placed: its shape, whether it is on, its luminance.
  const SurfaceEmitterShape& shape(int index) const { return bound_[static_cast<size_t>(index)].shape; }
  bool on(int index) const { return bound_[static_cast<size_t>(index)].placed; }
  int engine_calls() const { return engine_calls_; }  // since Bind: moves, rescales, removals

 private:
  struct Bound {
    SurfaceEmitterShape shape;           // built at Bind; Flush rewrites only the corners
    int corner_count = 0;
    int32_t base_q16[kMaxSurfaceEmitterCorners][3] = {};  // corners about the centre at scale 1
    int32_t centre_q16[3] = {};
    int32_t u_q16[3] = {}, v_q16[3] = {};  // unit vectors, 65536 = 1
    int32_t luminance_q12[3] = {};
    int32_t x_range_q16[2] = {}, y_range_q16[2] = {}, size_range_q16[2] = {};
    int32_t level[kParamCount] = {};     // Q1.15, by Param
    bool placed = false, geometry_dirty = true, luminance_dirty = true;
  };
  // Corners for the levels given (Q1.15 x, y, size) into shape.corners_q16.
  static void Shape(Bound& b, int32_t x_q15, int32_t y_q15, int32_t size_q15);
  static void Luminance(const Bound& b, LightQ12 out[3]);

  Engine* engine_ = nullptr;
  std::vector<Bound> bound_;
  int engine_calls_ = 0;
};

}  // namespace relight::control
