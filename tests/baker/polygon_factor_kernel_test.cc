// The form factors' vectorised edge terms (polygon_factor_kernel.h) against
// the one-point function, and their arctangent against the C library's.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "contour_integral.h"
#include "form_factors.h"
#include "polygon_factor_kernel.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Distance in units in the last place between two finite doubles of one sign.
int64_t UlpDistance(double a, double b) {
  int64_t ia, ib;
  std::memcpy(&ia, &a, sizeof a);
  std::memcpy(&ib, &b, sizeof b);
  return ia > ib ? ia - ib : ib - ia;
}

TEST(EdgeAngle, MatchesAtan2WithinTwoUlpOverEveryOctant) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> mantissa(0.5, 1.0);
  std::uniform_int_distribution<int> exponent(-30, 30);
  int64_t worst = 0;
  int near_boundary = 0;
  for (int k = 0; k < 400000; ++k) {
    const double y = std::ldexp(mantissa(rng), exponent(rng));
    // |x| within a few binades of y, so every reduction branch is taken.
    double x = std::ldexp(mantissa(rng), std::ilogb(y) + exponent(rng) % 4);
    if (k % 2 == 1) x = -x;
    const double ratio = std::min(y, std::abs(x)) / std::max(y, std::abs(x));
    if (std::abs(ratio - 0.66) < 0.01) ++near_boundary;
    const int64_t d = UlpDistance(EdgeAngle(y, x), std::atan2(y, x));
    if (d > worst) worst = d;
  }
  EXPECT_LE(worst, 2);
  EXPECT_GT(near_boundary, 100);  // both sides of the 0.66 split were checked
  // The axes and diagonals.
  EXPECT_EQ(EdgeAngle(0, 1), 0.0);
  EXPECT_NEAR(EdgeAngle(0, -1), kPi, 1e-15);
  EXPECT_NEAR(EdgeAngle(1, 0), kPi / 2, 1e-16);
  EXPECT_NEAR(EdgeAngle(2, 2), kPi / 4, 1e-16);
  EXPECT_NEAR(EdgeAngle(3, -3), 3 * kPi / 4, 1e-15);
  EXPECT_LE(UlpDistance(EdgeAngle(1e-300, 1), std::atan2(1e-300, 1)), 1);
}

// A convex polygon of `corners` corners around `centre` in the plane with unit
// normal n (counter-clockwise seen from the front).
std::vector<Vec3> Polygon(const Vec3& centre, const Vec3& n, int corners, double radius, double phase) {
  const Vec3 helper = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  Vec3 u{helper[1] * n[2] - helper[2] * n[1], helper[2] * n[0] - helper[0] * n[2],
         helper[0] * n[1] - helper[1] * n[0]};
  const double len = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  for (double& c : u) c /= len;
  const Vec3 v{n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0]};
  std::vector<Vec3> out;
  for (int k = 0; k < corners; ++k) {
    const double a = phase + 2 * kPi * k / corners;
    const double cu = radius * std::cos(a), cv = radius * std::sin(a);
    out.push_back({centre[0] + cu * u[0] + cv * v[0], centre[1] + cu * u[1] + cv * v[1],
                   centre[2] + cu * u[2] + cv * v[2]});
  }
  return out;
}

Vec3 UnitVector(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  const Vec3 v{g(rng), g(rng), g(rng)};
  const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / len, v[1] / len, v[2] / len};
}

TEST(PolygonFactorKernel, EveryPointGetsTheOnePointFunctionsBits) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> coord(-2, 2), size(0.01, 1.5), unit(0, 1);
  int back = 0, clipped = 0, whole = 0, compared = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const Vec3 receiver_normal = UnitVector(rng);
    const Vec3 poly_normal = UnitVector(rng);
    const int corners = 3 + trial % 4;  // 3 to 6, as hierarchy nodes have
    const std::vector<Vec3> poly =
        Polygon({coord(rng), coord(rng), coord(rng)}, poly_normal, corners, size(rng), unit(rng));
    // Up to 32 points (the largest sample set), so a batch can be partly filled.
    std::vector<PatchSample> points(static_cast<size_t>(1 + trial % 32));
    for (PatchSample& s : points) s.point = {coord(rng), coord(rng), coord(rng)};
    std::vector<double> batch(points.size(), -1.0);
    PointsToPolygonFormFactors(points.data(), points.size(), receiver_normal, poly.data(), corners,
                               poly_normal, batch.data());
    for (size_t i = 0; i < points.size(); ++i) {
      const Vec3& x = points[i].point;
      const double one = PointToPolygonFormFactor(x, receiver_normal, poly.data(), corners, poly_normal);
      ASSERT_EQ(std::memcmp(&one, &batch[i], sizeof one), 0)
          << "trial " << trial << " point " << i << ": " << one << " against " << batch[i];
      ++compared;
      const double h = poly_normal[0] * (x[0] - poly[0][0]) + poly_normal[1] * (x[1] - poly[0][1]) +
                       poly_normal[2] * (x[2] - poly[0][2]);
      if (h <= 0) {
        ++back;
        continue;
      }
      bool in_front = true;
      for (const Vec3& c : poly) {
        in_front = in_front && receiver_normal[0] * (c[0] - x[0]) + receiver_normal[1] * (c[1] - x[1]) +
                                       receiver_normal[2] * (c[2] - x[2]) >= 0;
      }
      ++(in_front ? whole : clipped);
    }
  }
  // Each route of the batch function was taken many times.
  EXPECT_GT(back, 1000);
  EXPECT_GT(clipped, 1000);
  EXPECT_GT(whole, 1000);
  EXPECT_GT(compared, 40000);
}

}  // namespace
}  // namespace relight::baker
