// Picking a point of the scene in the rendered view (Dobashi 4.2: "aim this
// light at that point"): the ID pass says which triangle, hence which input
// surface, a pixel shows; the depth buffer gives the world point, which
// Engine::AimAt turns into pan and tilt.
//
// Thread safety: that of OsMesaFrame (one thread).
#pragma once

#include <cstdint>

#include "relight/bake/bake.h"
#include "relight/render/osmesa_frame.h"
#include "relight/base/status.h"

namespace relight {

struct PickResult {
  uint32_t triangle = 0;
  uint32_t surface = 0;       // index into BakeMesh::surface_names
  float world_m[3] = {0, 0, 0};
  int32_t world_q16[3] = {0, 0, 0};  // Q16.16 metres, for Engine::AimAt
};

// Draws the ID pass of `frame` (initialised with `mesh` and its camera set)
// and reads pixel (x, y), x right and y down from the top-left corner.
// kInvalidArgument outside the frame, kNotFound where it shows background.
Status PickPixel(OsMesaFrame* frame, const BakeMesh& mesh, int x, int y, PickResult* out);

}  // namespace relight
