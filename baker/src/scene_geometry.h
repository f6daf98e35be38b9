// Geometry the scene loader derives from its shorthand objects: the faces of
// a box, the points of a rectangular calculation grid, the placement of an
// OBJ mesh. Plain float64 math, no validation (the loader validates).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "relight/baker/scene.h"

namespace relight::baker {

// Face labels of a box, in output order: the face at max x is "+x".
inline constexpr std::array<const char*, 6> kBoxFaceLabels = {"+x", "-x", "+y", "-y", "+z", "-z"};

// The four corners of box face `face` (index into kBoxFaceLabels), counter-
// clockwise seen from outside (inward: from inside). The box spans
// [min, max] and is then turned by rotate_z_deg about its vertical centre axis.
std::vector<Vec3> BoxFace(const Vec3& min, const Vec3& max, double rotate_z_deg, bool inward,
                          int face);

// Cell centres of a columns x rows grid spanning origin + [0,1] u + [0,1] v,
// row-major: point r * columns + c lies at origin + (c + 0.5)/columns u + (r + 0.5)/rows v.
std::vector<Vec3> RectangleGridPoints(const Vec3& origin, const Vec3& u, const Vec3& v, int columns,
                                      int rows);

// Where an OBJ point lands: optionally y-up to z-up ((x, y, z) -> (x, -z, y)),
// then scaled per axis, turned by rotate_z_deg about the z axis, translated.
struct MeshPlacement {
  bool y_up = false;
  Vec3 scale{1, 1, 1};
  double rotate_z_deg = 0;
  Vec3 translate{0, 0, 0};
  Vec3 Apply(const Vec3& p) const;
};

}  // namespace relight::baker
