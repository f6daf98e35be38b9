// The form factor from a differential area to a convex polygon, in fixed
// point: Lambert's contour integral, as the baker's PointToPolygonFormFactor
// (baker/src/form_factors.h) computes it in float64, with the polygon first
// clipped to the half-space in front of the point. Adaptive refine (AR) uses
// it for links the baker did not make (surface_emitter_refine.h).
// Integer-only, no allocation; thread-safe.
#pragma once

#include <cstdint>

namespace relight {

// Largest polygon the kernel takes: a node (6 corners) clipped by an emitter
// (8 edges), then by the receiver's plane.
inline constexpr int kMaxFactorPolygonCorners = 16;

// F from a point x (Q16.16 metres) with unit normal n_q30 (Q1.30) to the
// polygon (count corners, Q16.16 metres, either winding), unoccluded,
// UQ0.32 (2^32 = 1, saturated below it). 0 when the polygon lies behind x's
// plane or count < 3 or > kMaxFactorPolygonCorners. Points on the polygon's
// own plane see none of it (the caller gives the polygon's lit side by
// placing x in front of it).
uint32_t PointToPolygonFactorQ32(const int64_t x_q16[3], const int32_t n_q30[3],
                                 const int64_t (*poly_q16)[3], int count);

}  // namespace relight
