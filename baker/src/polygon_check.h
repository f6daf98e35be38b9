// Whether a polygon can be a Surface (scene.h): 3 or 4 corners, edges long
// enough, not a sliver, planar within tolerance, strictly convex. Shared by
// the scene loader (inline quads, box faces, transformed OBJ faces) and the
// OBJ loader (which splits quads that fail into triangles).
#pragma once

#include <string>
#include <vector>

#include "relight/baker/scene.h"

namespace relight::baker {

inline constexpr double kMinEdgeM = 1e-5;            // 0.01 mm: shorter edges are degenerate
inline constexpr double kMinAreaRatio = 1e-6;        // area / longest edge^2 below this: a sliver
inline constexpr double kPlanarityRatio = 0.005;     // max corner offset / longest diagonal
inline constexpr double kConvexSinTolerance = 1e-6;  // sin of the turn at a corner

// Corner offset from the mean plane, as a fraction of the longest diagonal,
// below which a quad counts as exactly planar. Downstream code (the mesher)
// wants exact planes: the scene loader projects a quad inside the user
// tolerance (kPlanarityRatio) but not this flat onto its mean plane, the
// OBJ loader splits it into two triangles.
inline constexpr double kFlatRatio = 1e-7;

// Newell's normal: its length is twice the polygon's area, its direction the
// side from which the corners run counter-clockwise.
Vec3 NewellNormal(const std::vector<Vec3>& corners);

// An empty string when the polygon is usable, otherwise what is wrong with
// it, phrased to follow "quad 'x': " ("not planar: corner 3 is ...").
std::string PolygonProblem(const std::vector<Vec3>& corners);

// True for a triangle, or a quad whose corners are all within kFlatRatio of
// its diagonal from the mean plane.
bool IsFlat(const std::vector<Vec3>& corners);

// The corners moved along the Newell normal onto the plane through their
// centroid (a quad with non-zero area).
std::vector<Vec3> ProjectToMeanPlane(const std::vector<Vec3>& corners);

// A usable quad as two triangles split along its shorter diagonal, both
// keeping its winding.
std::vector<std::vector<Vec3>> SplitQuad(const std::vector<Vec3>& quad);

}  // namespace relight::baker
