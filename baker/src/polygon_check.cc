// Validation of the planar convex polygons every Surface must be.
#include "polygon_check.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "vec3_math.h"

namespace relight::baker {

namespace {

std::string Format(const char* fmt, double a, double b = 0, double c = 0) {
  char buf[256];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

// Largest distance of a corner from the plane through the centroid with the
// Newell normal, and the longest diagonal, for a quad with non-zero area.
void PlaneOffset(const std::vector<Vec3>& quad, double* max_offset, int* worst_corner,
                 double* diagonal) {
  const Vec3 n = NewellNormal(quad);
  const Vec3 unit = Scale(n, 1.0 / Length(n));
  Vec3 centroid{0, 0, 0};
  for (const Vec3& p : quad) centroid = Add(centroid, Scale(p, 0.25));
  *diagonal = std::max(Length(Sub(quad[2], quad[0])), Length(Sub(quad[3], quad[1])));
  *max_offset = 0;
  *worst_corner = 0;
  for (int i = 0; i < 4; ++i) {
    const double offset = std::fabs(Dot(Sub(quad[static_cast<size_t>(i)], centroid), unit));
    if (offset > *max_offset) {
      *max_offset = offset;
      *worst_corner = i;
    }
  }
}

}  // namespace

Vec3 NewellNormal(const std::vector<Vec3>& corners) {
  Vec3 n{0, 0, 0};
  if (corners.empty()) return n;
  const size_t count = corners.size();
  // Relative to corner 0: the same sum, without cancellation far from the origin.
  for (size_t i = 1; i + 1 < count; ++i) {
    const Vec3 c = Cross(Sub(corners[i], corners[0]), Sub(corners[i + 1], corners[0]));
    for (int k = 0; k < 3; ++k) n[k] += c[k];
  }
  return n;
}

std::string PolygonProblem(const std::vector<Vec3>& corners) {
  const size_t count = corners.size();
  if (count != 3 && count != 4) return "needs 3 or 4 corners";
  for (const Vec3& p : corners) {
    for (double x : p) {
      if (!std::isfinite(x)) return "has a corner that is not finite";
    }
  }
  double longest_edge = 0;
  for (size_t i = 0; i < count; ++i) {
    const double e = Length(Sub(corners[(i + 1) % count], corners[i]));
    if (e < kMinEdgeM) {
      return Format("degenerate: corners %.0f and %.0f coincide (edge %.3g m)", double(i + 1),
                    double((i + 1) % count + 1), e);
    }
    longest_edge = std::max(longest_edge, e);
  }
  const Vec3 n = NewellNormal(corners);
  const double area = 0.5 * Length(n);
  if (area < kMinAreaRatio * longest_edge * longest_edge) {
    return Format("degenerate: its corners are (nearly) collinear (area %.3g m^2)", area);
  }
  const Vec3 unit{n[0] / (2 * area), n[1] / (2 * area), n[2] / (2 * area)};
  if (count == 4) {
    // Planarity: distance of each corner from the mean plane (centroid, Newell normal).
    double offset = 0, diagonal = 0;
    int worst = 0;
    PlaneOffset(corners, &offset, &worst, &diagonal);
    const double tolerance = kPlanarityRatio * diagonal;
    if (offset > tolerance) {
      return Format(
          "not planar: corner %.0f is %.1f mm off the mean plane (tolerance %.1f mm, "
          "0.5%% of the diagonal)",
          double(worst + 1), offset * 1e3, tolerance * 1e3);
    }
    // Strict convexity: every corner turns the same way as the polygon as a whole.
    for (size_t i = 0; i < 4; ++i) {
      const Vec3 in = Sub(corners[i], corners[(i + 3) % 4]);
      const Vec3 out = Sub(corners[(i + 1) % 4], corners[i]);
      const double turn = Dot(Cross(in, out), unit);
      if (turn <= kConvexSinTolerance * Length(in) * Length(out)) {
        return Format(
            "not strictly convex at corner %.0f (corners must run counter-clockwise "
            "around a convex outline, seen from the lit side)",
            double(i + 1));
      }
    }
  }
  return {};
}

bool IsFlat(const std::vector<Vec3>& corners) {
  if (corners.size() != 4) return true;
  double offset = 0, diagonal = 0;
  int worst = 0;
  PlaneOffset(corners, &offset, &worst, &diagonal);
  return offset <= kFlatRatio * diagonal;
}

std::vector<Vec3> ProjectToMeanPlane(const std::vector<Vec3>& corners) {
  const Vec3 n = NewellNormal(corners);
  const Vec3 unit = Scale(n, 1.0 / Length(n));
  Vec3 centroid{0, 0, 0};
  for (const Vec3& p : corners) {
    centroid = Add(centroid, Scale(p, 1.0 / static_cast<double>(corners.size())));
  }
  std::vector<Vec3> out;
  for (const Vec3& p : corners) out.push_back(Sub(p, Scale(unit, Dot(Sub(p, centroid), unit))));
  return out;
}

std::vector<std::vector<Vec3>> SplitQuad(const std::vector<Vec3>& q) {
  if (Length(Sub(q[2], q[0])) <= Length(Sub(q[3], q[1]))) {
    return {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
  }
  return {{q[1], q[2], q[3]}, {q[1], q[3], q[0]}};
}

}  // namespace relight::baker
