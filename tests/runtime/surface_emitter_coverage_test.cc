// FE coverage (surface_emitter_coverage.h): the area an emitter polygon
// covers, summed over the leaves it touches (fraction x leaf area), equals the
// float64 area of polygon n surface, computed leaf by leaf in the test, within
// 1e-6 relative: inside one leaf, across node boundaries, a 1.5 mm sliver,
// more than the whole surface, on a tilted triangle's hexagonal nodes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "radiosity_vec.h"
#include "relight/bake/bake.h"
#include "relight/baker/baker.h"
#include "surface_emitter_coverage.h"
#include "surface_emitter_test_support.h"
#include "test_scenes.h"

namespace relight::testing {
namespace {

using namespace baker::radiosity_vec;

constexpr Vec3 kLeanA{0.2, 0.2, 0.05}, kLeanB{0.8, 0.25, 0.1}, kLeanC{0.45, 0.7, 0.5};

// A 1 m box of 0.1 m patches and a tilted triangle standing in it.
const Bake& TestBake() {
  static const Bake bake = [] {
    baker::Scene scene = baker::test_scenes::ClosedBox(0.1, {0.5, 0.5, 0.5});
    scene.surfaces.push_back(baker::test_scenes::Triangle("lean-to", kLeanA, kLeanB, kLeanC));
    baker::BakeOptions options;
    options.solver = baker::SolverKind::kHierarchical;
    return baker::Baker(scene, options).Bake();
  }();
  return bake;
}

struct Covered {
  double runtime_m2 = 0, reference_m2 = 0;
  int leaves = 0, full_leaves = 0;
};

Covered Cover(const std::string& surface, const std::vector<Vec3>& corners) {
  const Bake& bake = TestBake();
  const BakeHierarchy& h = *bake.hierarchy;
  const SurfaceEmitterShape shape = MakeShape(surface, corners);
  const uint32_t root = SurfaceRoot(bake, surface);
  std::vector<int64_t> fraction(h.node_count(), 0);
  const Status st = SurfaceEmitterCoverageQ32(h, bake.mesh, root, shape.corners_q16,
                                              shape.corner_count, fraction.data());
  EXPECT_TRUE(st.ok()) << st.ToString();
  // The reference clips the emitter as the runtime received it (Q16.16).
  std::vector<Vec3> emitter;
  for (int k = 0; k < shape.corner_count; ++k)
    emitter.push_back({shape.corners_q16[k][0] / 65536.0, shape.corners_q16[k][1] / 65536.0,
                       shape.corners_q16[k][2] / 65536.0});
  const std::vector<Vec3> root_corners = NodeCorners(bake, root);
  const AxisPlane plane(Cross(root_corners[1] - root_corners[0], root_corners[2] - root_corners[0]));
  const std::vector<Vec2> clip = plane.Polygon(emitter);
  Covered out;
  for (uint32_t k = 0; k < h.node_count(); ++k) {
    if (!h.leaf(k)) continue;
    if (h.node_surface[k] != h.node_surface[root]) {
      EXPECT_EQ(fraction[k], 0);
      continue;
    }
    const std::vector<Vec3> leaf = NodeCorners(bake, k);
    const double area = Area3(leaf);
    const std::vector<Vec2> leaf2 = plane.Polygon(leaf);
    const std::vector<Vec2> cut = ClipConvex(leaf2, clip);
    if (cut.size() >= 3) out.reference_m2 += area * SignedArea(cut) / SignedArea(leaf2);
    if (fraction[k] == 0) continue;
    out.runtime_m2 += area * std::ldexp(static_cast<double>(fraction[k]), -kCoverageFracBits);
    ++out.leaves;
    if (fraction[k] == int64_t{1} << kCoverageFracBits) ++out.full_leaves;
  }
  std::printf("[ measured ] %s, %zu corners: covered %.9f m^2 (reference %.9f), %d leaves, "
              "relative error %.2e\n",
              surface.c_str(), corners.size(), out.runtime_m2, out.reference_m2, out.leaves,
              std::abs(out.runtime_m2 - out.reference_m2) / out.reference_m2);
  return out;
}

void ExpectArea(const Covered& c) {
  EXPECT_GT(c.reference_m2, 0);
  EXPECT_NEAR(c.runtime_m2, c.reference_m2, 1e-6 * c.reference_m2);
}

TEST(SurfaceEmitterCoverage, InsideOneLeaf) {
  const Covered c = Cover("ceiling", {{0.12, 0.13, 1}, {0.18, 0.14, 1}, {0.15, 0.19, 1}});
  ExpectArea(c);
  EXPECT_EQ(c.leaves, 1);
  EXPECT_EQ(c.full_leaves, 0);
}

TEST(SurfaceEmitterCoverage, AcrossNodeBoundaries) {
  const Covered c = Cover("ceiling", {{0.13, 0.21, 1}, {0.17, 0.66, 1}, {0.55, 0.83, 1},
                                      {0.86, 0.52, 1}, {0.71, 0.18, 1}});
  ExpectArea(c);
  EXPECT_GT(c.full_leaves, 10);       // inner nodes covered whole
  EXPECT_GT(c.leaves, c.full_leaves);  // and leaves cut by the edges
}

TEST(SurfaceEmitterCoverage, Sliver) {
  // About 1.5 mm wide, diagonally across the floor.
  const Covered c = Cover("floor", {{0.03, 0.05, 0}, {0.97, 0.93, 0}, {0.969, 0.932, 0}});
  ExpectArea(c);
  EXPECT_GT(c.leaves, 9);
  EXPECT_EQ(c.full_leaves, 0);
}

TEST(SurfaceEmitterCoverage, MoreThanTheWholeSurface) {
  const Covered c = Cover("wall -x", {{0, -0.5, -0.5}, {0, 1.5, -0.5}, {0, 1.5, 1.5}, {0, -0.5, 1.5}});
  ExpectArea(c);
  EXPECT_EQ(c.leaves, c.full_leaves);
  EXPECT_NEAR(c.runtime_m2, 1.0, 1e-6);
}

TEST(SurfaceEmitterCoverage, TiltedTriangleSurface) {
  const auto at = [](double a, double b) { return kLeanA + a * (kLeanB - kLeanA) + b * (kLeanC - kLeanA); };
  const Covered c = Cover("lean-to", {at(0.1, 0.1), at(0.6, 0.05), at(0.5, 0.4), at(0.15, 0.5)});
  ExpectArea(c);
  EXPECT_GT(c.full_leaves, 0);
}

}  // namespace
}  // namespace relight::testing
