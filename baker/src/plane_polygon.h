// Float64 polygons in a plane (2-D, after projecting a surface along its
// normal's largest axis): signed area and clipping by a convex polygon.
// Used by the naive emitter ground truth and by the run-time emitter tests'
// references, so both clip the same way.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

namespace relight::baker {

using Vec2 = std::array<double, 2>;

// Positive for a counter-clockwise polygon.
inline double SignedArea(const std::vector<Vec2>& p) {
  double sum = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    const Vec2& a = p[i];
    const Vec2& b = p[(i + 1) % p.size()];
    sum += a[0] * b[1] - b[0] * a[1];
  }
  return 0.5 * sum;
}

// Sutherland-Hodgman of any polygon by a convex counter-clockwise one.
inline std::vector<Vec2> ClipConvex(std::vector<Vec2> poly, const std::vector<Vec2>& clip) {
  for (size_t e = 0; e < clip.size() && !poly.empty(); ++e) {
    const Vec2 a = clip[e], b = clip[(e + 1) % clip.size()];
    const auto side = [&](const Vec2& p) {
      return (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
    };
    std::vector<Vec2> out;
    for (size_t i = 0; i < poly.size(); ++i) {
      const Vec2 s = poly[(i + poly.size() - 1) % poly.size()], p = poly[i];
      const double ds = side(s), dp = side(p);
      if ((ds < 0) != (dp < 0)) {
        const double t = ds / (ds - dp);
        out.push_back({s[0] + t * (p[0] - s[0]), s[1] + t * (p[1] - s[1])});
      }
      if (dp >= 0) out.push_back(p);
    }
    poly = out;
  }
  return poly;
}

}  // namespace relight::baker
