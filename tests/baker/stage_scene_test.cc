// fixtures/stage.toml (issue 12 item 5) is the theatre it claims to be: a
// dark 12 x 10 x 6 m room, a riser with a calculation grid on it, light
// flats, and 48 hanging heads on two trusses whose beams are their QLC+
// types' (zoom = the lens range, the type's lumens, beam angle at the range's
// midpoint), checked numerically through Lid::Evaluate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "relight/baker/scene.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;

const Surface* Find(const Scene& scene, const std::string& name) {
  for (const Surface& s : scene.surfaces) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

double MaxChannel(const Rgb& r) { return std::max({r[0], r[1], r[2]}); }

// Full angle (degrees) at which the intensity falls to half its peak, by bisection.
double BeamAngleDeg(const Lid& lid) {
  const double half = 0.5 * lid.Evaluate(0.0);
  double lo = 0, hi = 90;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (lid.Evaluate(mid) > half ? lo : hi) = mid;
  }
  return 2 * lo;
}

// Luminous flux (lm) of an axisymmetric LID: 2 pi * integral of I sin(gamma).
double FluxLm(const Lid& lid) {
  const int n = 20000;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double g = (i + 0.5) * 180.0 / n;
    sum += lid.Evaluate(g) * std::sin(g * kPi / 180) * (kPi / n);
  }
  return 2 * kPi * sum;
}

TEST(StageScene, IsADarkTheatreWithARiserFlatsAndAGrid) {
  const Scene scene = LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/stage.toml");
  EXPECT_EQ(scene.name, "stage");
  const Surface* floor = Find(scene, "room/-z");
  ASSERT_NE(floor, nullptr);
  double xmax = 0, ymax = 0, zmax = 0;
  for (const Surface& s : scene.surfaces) {
    if (s.name.rfind("room/", 0) != 0) continue;
    EXPECT_LE(MaxChannel(s.reflectance), 0.1) << s.name << ": the room is dark";
    for (const Vec3& c : s.corners) {
      xmax = std::max(xmax, c[0]), ymax = std::max(ymax, c[1]), zmax = std::max(zmax, c[2]);
    }
  }
  EXPECT_NEAR(xmax, 12, 1e-9);
  EXPECT_NEAR(ymax, 10, 1e-9);
  EXPECT_NEAR(zmax, 6, 1e-9);
  const Surface* riser = Find(scene, "riser/+z");
  ASSERT_NE(riser, nullptr);
  const double riser_z = riser->corners[0][2];
  EXPECT_GE(riser_z, 0.6);
  EXPECT_LE(riser_z, 1.0);
  for (const char* flat : {"flat_centre", "flat_left", "flat_right"}) {
    const Surface* s = Find(scene, flat);
    ASSERT_NE(s, nullptr) << flat;
    EXPECT_GE(MaxChannel(s->reflectance), 0.4) << flat << ": lighter paint, so interreflection shows";
  }
  ASSERT_EQ(scene.grids.size(), 1u);
  EXPECT_EQ(scene.grids[0].name, "stage_floor");
  for (const Vec3& p : scene.grids[0].points) {
    EXPECT_GT(p[2], riser_z);
    EXPECT_LT(p[2], riser_z + 0.05);
    EXPECT_GE(p[1], 5.0);  // on the riser (upstage half)
  }
}

TEST(StageScene, FortyEightHeadsOnTwoTrussesWithTheirTypesBeams) {
  const Scene scene = LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/stage.toml");
  const Surface* truss_bottom[2] = {Find(scene, "truss_ds/-z"), Find(scene, "truss_us/-z")};
  ASSERT_NE(truss_bottom[0], nullptr);
  ASSERT_NE(truss_bottom[1], nullptr);
  int heads[2] = {0, 0}, spots = 0, washes = 0, front = 0;
  for (const Luminaire& l : scene.luminaires) {
    SCOPED_TRACE(l.name);
    if (l.name.rfind("foh_", 0) == 0) {
      ++front;
      continue;
    }
    const int truss = l.name.rfind("ds_", 0) == 0 ? 0 : 1;
    ASSERT_TRUE(truss == 0 || l.name.rfind("us_", 0) == 0);
    ++heads[truss];
    EXPECT_EQ(l.mounting, MountingKind::kHanging);
    // Just under its truss: within its footprint in y, below its bottom face.
    const Surface& t = *truss_bottom[truss];
    double ymin = 1e9, ymax = -1e9;
    for (const Vec3& c : t.corners) ymin = std::min(ymin, c[1]), ymax = std::max(ymax, c[1]);
    EXPECT_GT(l.position[1], ymin);
    EXPECT_LT(l.position[1], ymax);
    EXPECT_LT(l.position[2], t.corners[0][2]);
    EXPECT_GT(l.position[2], t.corners[0][2] - 0.5);
    // The type's beam: zoom over the lens range, half-peak angle at its midpoint, the type's lumens.
    ASSERT_EQ(l.lid.kind, LidKind::kBeam);
    const bool spot = l.name.find("_spot_") != std::string::npos;
    const double lens_min = spot ? 12 : 11, lens_max = spot ? 36 : 58, lumens = spot ? 12700 : 3850;
    const double beam = BeamAngleDeg(l.lid);
    EXPECT_GE(beam, lens_min);
    EXPECT_LE(beam, lens_max);
    EXPECT_NEAR(beam, 0.5 * (lens_min + lens_max), 1.0) << "the lens range's midpoint";
    EXPECT_NEAR(FluxLm(l.lid), lumens, 0.02 * lumens);
    EXPECT_EQ(l.lid.zoom_min_deg, lens_min);
    EXPECT_EQ(l.lid.zoom_max_deg, lens_max);
    EXPECT_EQ(l.sh_degree, 8);
    EXPECT_NEAR(l.pan_range_deg, 540, 1e-9);
    EXPECT_NEAR(l.tilt_range_deg, spot ? 268 : 232, 1e-9);  // the .qxf's <Focus TiltMax>
    spots += spot;
    washes += !spot;
  }
  EXPECT_EQ(heads[0], 24);
  EXPECT_EQ(heads[1], 24);
  EXPECT_EQ(spots, 24);
  EXPECT_EQ(washes, 24);
  EXPECT_GE(front, 2);
}

}  // namespace
}  // namespace relight::baker
