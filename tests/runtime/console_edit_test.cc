// Console-style aiming (16-bit pan/tilt over the fixture's ranges, aiming at
// a point inside them) and beam editing (Dobashi 4.1, Eq. 21) in the engine.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "console_aim.h"
#include "relight/baker/baker.h"
#include "relight/baker/fixture_frame.h"
#include "relight/engine/engine.h"

namespace relight {
namespace {

Q16_16 Deg(double d) { return Q16_16::FromRaw(static_cast<int32_t>(std::llround(d * 65536.0))); }
double FromDeg(Q16_16 d) { return d.raw() / 65536.0; }

TEST(ConsoleAim, SixteenBitValuesSpanTheRangesAroundHome) {
  const int32_t pan_range = 540 << 16, tilt_range = 270 << 16;
  EXPECT_EQ(ConsoleToDegrees(32768, pan_range), Deg(0));
  EXPECT_EQ(ConsoleToDegrees(0, pan_range), Deg(-270));
  EXPECT_EQ(ConsoleToDegrees(0, tilt_range), Deg(-135));
  EXPECT_NEAR(FromDeg(ConsoleToDegrees(65535, pan_range)), 270.0 - 540.0 / 65536, 1e-4);
  // coarse << 8 | fine: one fine step is range / 65536.
  const uint16_t v = static_cast<uint16_t>(0x90 << 8 | 0x40);
  EXPECT_NEAR(FromDeg(ConsoleToDegrees(v, pan_range)), (v - 32768) * 540.0 / 65536, 1e-4);
  for (uint32_t value = 0; value <= 65535; value += 97) {
    const auto u = static_cast<uint16_t>(value);
    EXPECT_EQ(DegreesToConsole(ConsoleToDegrees(u, pan_range), pan_range), u);
  }
  EXPECT_EQ(DegreesToConsole(Deg(1000), pan_range), 65535);
  EXPECT_EQ(DegreesToConsole(Deg(-1000), pan_range), 0);
}

TEST(ConsoleAim, ChoosesTheReachablePairNearestTheCurrentAim) {
  Q16_16 pan, tilt;
  // 540 degrees of pan: 170 and -190 both reach; from -170 the nearer is -190.
  ASSERT_TRUE(ChooseAimInRange(Deg(170), Deg(40), 540 << 16, 270 << 16, Deg(-170), Deg(40), &pan, &tilt));
  EXPECT_EQ(pan, Deg(-190));
  EXPECT_EQ(tilt, Deg(40));
  // With 360 degrees of pan, -190 is out: the flipped pair (-10, -40) is nearer than 170.
  ASSERT_TRUE(ChooseAimInRange(Deg(170), Deg(40), 360 << 16, 270 << 16, Deg(-20), Deg(-30), &pan, &tilt));
  EXPECT_EQ(pan, Deg(-10));
  EXPECT_EQ(tilt, Deg(-40));
  // A tilt of 150 needs more than 270 degrees of tilt range either way.
  EXPECT_FALSE(ChooseAimInRange(Deg(0), Deg(150), 540 << 16, 270 << 16, Deg(0), Deg(0), &pan, &tilt));
}

// A small real bake: a 4 m floor under one axisymmetric luminaire.
struct SmallBake {
  Bake bake;
  baker::Scene scene;
};

SmallBake MakeSmallBake(baker::MountingKind mounting) {
  SmallBake out;
  baker::Scene& s = out.scene;
  s.name = "floor";
  s.path = "console_edit_test";
  s.patch_size_m = 1.0;
  baker::Surface floor;
  floor.name = "floor";
  floor.corners = {{-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0}};
  s.surfaces.push_back(floor);
  baker::Luminaire lum;
  lum.name = "spot";
  lum.position = {0, 0, mounting == baker::MountingKind::kStanding ? -1.0 : 2.5};
  lum.mounting = mounting;
  lum.sh_degree = 4;
  lum.lid.kind = baker::LidKind::kCosPower;
  lum.lid.exponent = 4;
  lum.lid.spread_deg = 90;
  lum.lid.peak_cd = 1000;
  s.luminaires.push_back(lum);
  baker::CalcGrid grid;
  grid.name = "g";
  for (int i = 0; i < 25; ++i) {
    grid.points.push_back({-1.6 + 0.8 * (i % 5), -1.6 + 0.8 * (i / 5), 0.01});
    grid.normals.push_back({0, 0, 1});
  }
  s.grids.push_back(grid);
  s.camera.position = {0, -3, 2};
  s.camera.target = {0, 0, 0};
  baker::BakeOptions options;
  options.threads = 2;
  options.lid_samples = 180;
  baker::Baker b(s, options);
  out.bake = b.Bake();
  return out;
}

TEST(ConsoleAim, EngineAimsAtAPointWithinTheRangesAndBy16BitValues) {
  SmallBake small = MakeSmallBake(baker::MountingKind::kHanging);
  small.bake.luminaires[0].pan_range = 360 << 16;
  Engine engine;
  ASSERT_TRUE(engine.Open(small.bake).ok());
  const baker::Vec3 pos = small.scene.luminaires[0].position;
  for (const baker::Vec3& target : {baker::Vec3{1.5, 0.5, 0}, baker::Vec3{-1.2, -1.7, 0.3},
                                    baker::Vec3{0.0, 0.0, 0.0}, baker::Vec3{-3, 1, 1}}) {
    int32_t t16[3];
    for (int i = 0; i < 3; ++i) t16[i] = static_cast<int32_t>(std::llround(target[i] * 65536));
    ASSERT_TRUE(engine.AimAt(0, t16).ok());
    const FixtureState st = engine.state(0);
    EXPECT_LE(std::abs(FromDeg(st.pan_deg)), 180.0);
    EXPECT_LE(std::abs(FromDeg(st.tilt_deg)), 135.0);
    const baker::FixtureFrame f = baker::MakeFixtureFrame(
        {baker::MountingKind::kHanging, 0, FromDeg(st.pan_deg), FromDeg(st.tilt_deg), 0});
    baker::Vec3 d{target[0] - pos[0], target[1] - pos[1], target[2] - pos[2]};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    EXPECT_NEAR((d[0] * f.axis[0] + d[1] * f.axis[1] + d[2] * f.axis[2]) / len, 1.0, 1e-9);
  }
  // Straight up from a hanging fixture: tilt 180 is beyond +-135.
  const int32_t above[3] = {0, 0, 5 << 16};
  EXPECT_EQ(engine.AimAt(0, above).code(), StatusCode::kOutOfRange);
  const int32_t same[3] = {0, 0, static_cast<int32_t>(2.5 * 65536)};
  EXPECT_EQ(engine.AimAt(0, same).code(), StatusCode::kInvalidArgument);
  // 16-bit values through the bake's ranges (pan 360, tilt 270).
  ASSERT_TRUE(engine.SetPanTilt16(0, 32768 + 8192, 32768 - 4096).ok());
  EXPECT_EQ(engine.state(0).pan_deg, Deg(45));
  EXPECT_NEAR(FromDeg(engine.state(0).tilt_deg), -16.875, 1e-4);
  EXPECT_EQ(engine.SetPanTilt16(3, 0, 0).code(), StatusCode::kInvalidArgument);
}

// Dobashi 4.1: moving control points updates the weights incrementally
// (Eq. 21); the relit scene equals one opened with the edited LID.
TEST(BeamEditing, IncrementalEditsMatchABakeWithTheEditedLid) {
  const SmallBake small = MakeSmallBake(baker::MountingKind::kHanging);
  Engine edited;
  ASSERT_TRUE(edited.Open(small.bake).ok());
  ASSERT_TRUE(edited.SetPanTilt(0, Deg(20), Deg(25)).ok());
  // A wider, brighter beam with a shoulder: the polyline through five points.
  const Q16_16 gamma[] = {Deg(0), Deg(15), Deg(40), Deg(70), Deg(95)};
  const Q48_16 cd[] = {Q48_16::FromInt(1400), Q48_16::FromInt(1300), Q48_16::FromInt(900),
                       Q48_16::FromInt(200), Q48_16::FromInt(0)};
  ASSERT_TRUE(edited.SetLidControlPoints(0, gamma, cd, 5).ok());
  // And one sample moved on its own.
  int count = 0;
  const int64_t* samples = edited.lid_samples(0, &count);
  ASSERT_EQ(count, 181);
  ASSERT_TRUE(edited.SetLidSample(0, 30, Q48_16::FromRaw(samples[30] + (50 << 16))).ok());
  edited.Update();
  EXPECT_EQ(edited.last_update_luminaires_recombined(), 1);

  Bake fresh = small.bake;
  fresh.luminaires[0].lid.candela.assign(samples, samples + count);
  // The polyline itself at a few samples (gamma_k = k degrees here).
  EXPECT_EQ(samples[0], int64_t{1400} << 16);
  EXPECT_EQ(samples[15], int64_t{1300} << 16);
  EXPECT_NEAR(static_cast<double>(samples[55]) / 65536, 550.0, 1e-3);
  EXPECT_EQ(samples[100], 0);
  Engine reopened;
  ASSERT_TRUE(reopened.Open(fresh).ok());
  ASSERT_TRUE(reopened.SetPanTilt(0, Deg(20), Deg(25)).ok());
  reopened.Update();
  double worst = 0, peak = 0;
  for (uint32_t v = 0; v < edited.vertex_count() * 3; ++v) {
    worst = std::max(worst, std::abs(double(edited.vertex_luminance().raw()[v]) - reopened.vertex_luminance().raw()[v]));
    peak = std::max(peak, double(reopened.vertex_luminance().raw()[v]));
  }
  for (uint32_t p = 0; p < 25 * 3; ++p) {
    worst = std::max(worst, std::abs(double(edited.grid_illuminance(0).raw()[p]) - reopened.grid_illuminance(0).raw()[p]));
  }
  std::printf("beam edit: incremental vs from scratch, max %.0f LSB of LightQ12 (peak %.0f)\n", worst, peak);
  EXPECT_LE(worst, 4.0);
  EXPECT_GT(peak, 1000.0);

  // Errors, without allocation-sized messages.
  EXPECT_EQ(edited.SetLidSample(0, 181, Q48_16::FromInt(1)).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(edited.SetLidSample(0, 3, Q48_16::FromInt(-1)).code(), StatusCode::kOutOfRange);
  const Q16_16 bad_gamma[] = {Deg(5), Deg(10)};
  EXPECT_EQ(edited.SetLidControlPoints(0, bad_gamma, cd, 2).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace relight
