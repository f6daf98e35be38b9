// The point-to-polygon form factor (form_factors.h PointToPolygonFormFactor)
// for many receiving points against one polygon, vectorised over the points.
// Every result has the same bits as PointToPolygonFormFactor for that point:
// both sum contour_integral.h's edge terms in the same order.
#pragma once

#include <cstddef>

#include "mesher.h"

namespace relight::baker {

// out[i] = PointToPolygonFormFactor(points[i].point, n, poly, count, poly_normal) for i < point_count.
void PointsToPolygonFormFactors(const PatchSample* points, size_t point_count, const Vec3& n,
                                const Vec3* poly, int count, const Vec3& poly_normal, double* out);

}  // namespace relight::baker
