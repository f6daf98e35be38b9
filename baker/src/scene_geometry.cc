// Box faces, grid points and mesh placement for the scene loader.
#include "scene_geometry.h"

#include <algorithm>
#include <cmath>

#include "vec3_math.h"

namespace relight::baker {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Turns p by angle_deg about the vertical line through (cx, cy).
Vec3 RotateZ(const Vec3& p, double angle_deg, double cx, double cy) {
  const double a = angle_deg * kPi / 180.0;
  const double c = std::cos(a), s = std::sin(a);
  const double x = p[0] - cx, y = p[1] - cy;
  return {cx + c * x - s * y, cy + s * x + c * y, p[2]};
}

// Unit-cube corners of each face, counter-clockwise seen from outside
// (digits are x y z, 0 = min, 1 = max), in kBoxFaceLabels order.
constexpr int kFaceCorners[6][4][3] = {
    {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}},  // +x
    {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}},  // -x
    {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}},  // +y
    {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}},  // -y
    {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}},  // +z
    {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}},  // -z
};

}  // namespace

std::vector<Vec3> BoxFace(const Vec3& min, const Vec3& max, double rotate_z_deg, bool inward,
                          int face) {
  const double cx = 0.5 * (min[0] + max[0]), cy = 0.5 * (min[1] + max[1]);
  std::vector<Vec3> corners;
  for (const auto& unit : kFaceCorners[face]) {
    const Vec3 p{unit[0] ? max[0] : min[0], unit[1] ? max[1] : min[1], unit[2] ? max[2] : min[2]};
    corners.push_back(RotateZ(p, rotate_z_deg, cx, cy));
  }
  // Seen from inside the same corners run clockwise: reverse them.
  if (inward) std::reverse(corners.begin(), corners.end());
  return corners;
}

std::vector<Vec3> RectangleGridPoints(const Vec3& origin, const Vec3& u, const Vec3& v, int columns,
                                      int rows) {
  std::vector<Vec3> points;
  points.reserve(static_cast<size_t>(columns) * static_cast<size_t>(rows));
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < columns; ++c) {
      const double fu = (c + 0.5) / columns, fv = (r + 0.5) / rows;
      points.push_back(Add(origin, Add(Scale(u, fu), Scale(v, fv))));
    }
  }
  return points;
}

Vec3 MeshPlacement::Apply(const Vec3& p) const {
  Vec3 q = y_up ? Vec3{p[0], -p[2], p[1]} : p;
  for (int k = 0; k < 3; ++k) q[k] *= scale[k];
  return Add(RotateZ(q, rotate_z_deg, 0.0, 0.0), translate);
}

}  // namespace relight::baker
