// Engine::SetZoom (issue 12 item 3): a zooming "beam" LID baked on a small
// floor, zoomed at run time. The engine's LID samples against the float64
// beam model at the same angle (baker/include/relight/baker/beam_profile.h),
// the lumens held, the range clamped, exact return after zooming away and
// back, no work in black, no allocation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdint>
#include <vector>

#include "count_allocations.h"
#include "relight/baker/baker.h"
#include "relight/baker/beam_profile.h"
#include "relight/engine/engine.h"
#include "set_args.h"

namespace relight {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSamples = 720;  // M

Q16_16 Deg(double d) { return Q16_16::FromRaw(static_cast<int32_t>(std::llround(d * 65536))); }

baker::Luminaire Beam(const char* name, double x) {
  baker::Luminaire lum;
  lum.name = name;
  lum.position = {x, 0, 2.5};
  lum.sh_degree = 6;
  lum.sh_degree_given = true;
  lum.lid.kind = baker::LidKind::kBeam;
  lum.lid.beam_deg = 25;
  lum.lid.beam_exponent = baker::BeamProfileExponent(1.6);
  lum.lid.lumens = 1000;
  lum.lid.peak_cd = 1000 / baker::BeamLumensPerPeak(25, lum.lid.beam_exponent);
  lum.lid.zoom_min_deg = 10;
  lum.lid.zoom_max_deg = 50;
  return lum;
}

// A 4 m floor under a zooming beam and a plain cos spot.
struct ZoomBake {
  baker::Scene scene;
  Bake bake;
};

const ZoomBake& SmallZoomBake() {
  static const ZoomBake* baked = [] {
    auto* out = new ZoomBake;
    baker::Scene& s = out->scene;
    s.name = "zoom_floor";
    s.path = "zoom_engine_test";
    s.patch_size_m = 0.5;
    baker::Surface floor;
    floor.name = "floor";
    floor.corners = {{-2, -2, 0}, {2, -2, 0}, {2, 2, 0}, {-2, 2, 0}};
    s.surfaces.push_back(floor);
    s.luminaires.push_back(Beam("zoom", 0));
    baker::Luminaire plain = Beam("plain", 1);
    plain.lid.kind = baker::LidKind::kCosPower;
    plain.lid.exponent = 4;
    plain.lid.spread_deg = 90;
    s.luminaires.push_back(plain);
    s.camera.position = {0, -3, 2};
    s.camera.target = {0, 0, 0};
    baker::BakeOptions options;
    options.threads = 2;
    options.lid_samples = kSamples;
    baker::Baker b(s, options);
    out->bake = b.Bake();
    return out;
  }();
  return *baked;
}

// Flux of M+1 samples (cd) at gamma_k = pi k / M: 2 pi trapezoid of I sin.
double Lumens(const int64_t* q16, int count) {
  const int M = count - 1;
  double sum = 0;
  for (int k = 1; k < M; ++k) sum += static_cast<double>(q16[k]) / 65536.0 * std::sin(kPi * k / M);
  return 2 * kPi * sum * kPi / M;
}

TEST(Zoom, BakeCarriesTheZoomOfABeamOnly) {
  const Bake& bake = SmallZoomBake().bake;
  const BakeZoom& z = bake.luminaires[0].zoom;
  ASSERT_TRUE(z.present());
  EXPECT_EQ(z.min_deg, 10 << 16);
  EXPECT_EQ(z.max_deg, 50 << 16);
  EXPECT_EQ(z.default_deg, 25 << 16);
  EXPECT_EQ(z.lumens, int64_t{1000} << 16);
  EXPECT_EQ(z.profile.front(), 1 << 30);
  EXPECT_FALSE(bake.luminaires[1].zoom.present());
}

TEST(Zoom, SamplesFollowTheBeamModelAndHoldTheLumens) {
  const ZoomBake& zb = SmallZoomBake();
  Engine engine;
  ASSERT_TRUE(engine.Open(zb.bake).ok());
  EXPECT_EQ(engine.state(0).zoom_deg.raw(), 25 << 16);
  EXPECT_EQ(engine.state(1).zoom_deg.raw(), 0);
  for (double angle : {10.0, 17.5, 25.0, 38.25, 50.0}) {
    SCOPED_TRACE(angle);
    ASSERT_TRUE(engine.SetZoom(0, Deg(angle)).ok());
    engine.Update();
    int count = 0;
    const int64_t* samples = engine.lid_samples(0, &count);
    ASSERT_EQ(count, kSamples + 1);
    const baker::Lid exact = baker::ZoomedBeamLid(zb.scene.luminaires[0].lid, angle);
    double worst = 0;
    const double step = 180.0 / kSamples;
    for (int k = 0; k <= kSamples; ++k) {
      const double g = step * k;
      // The cut at 1 %: the engine's x_end is rounded to Q16.16, so a sample
      // within half a step of it may fall on either side.
      if (exact.Evaluate(g - step / 2) > 0 && exact.Evaluate(g + step / 2) == 0) continue;
      const double want = exact.Evaluate(g);
      worst = std::max(worst, std::abs(static_cast<double>(samples[k]) / 65536.0 - want) / exact.peak_cd);
    }
    EXPECT_LT(worst, 2e-3);  // of the peak; the cut at 1 % and the trapezoid rule
    EXPECT_NEAR(Lumens(samples, count), 1000.0, 0.5);
    // Half peak at half the beam angle: the angle is what the console set.
    const int half = static_cast<int>(std::lround(angle / 2 * kSamples / 180));
    EXPECT_NEAR(static_cast<double>(samples[half]) / static_cast<double>(samples[0]), 0.5, 0.02);
  }
}

TEST(Zoom, ClampsToTheRangeAndRefusesALuminaireWithoutZoom) {
  Engine engine;
  ASSERT_TRUE(engine.Open(SmallZoomBake().bake).ok());
  ASSERT_TRUE(engine.SetZoom(0, Deg(3)).ok());
  EXPECT_EQ(engine.state(0).zoom_deg.raw(), 10 << 16);
  ASSERT_TRUE(engine.SetZoom(0, Deg(170)).ok());
  EXPECT_EQ(engine.state(0).zoom_deg.raw(), 50 << 16);
  EXPECT_EQ(engine.SetZoom(1, Deg(20)).code(), StatusCode::kUnsupported);
  EXPECT_EQ(engine.state(1).zoom_deg.raw(), 0);
  EXPECT_EQ(engine.SetZoom(2, Deg(20)).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(engine.SetZoom(-1, Deg(20)).code(), StatusCode::kInvalidArgument);
}

TEST(Zoom, NarrowerIsBrighterOnAxisAndZoomingBackIsExact) {
  Engine engine;
  ASSERT_TRUE(engine.Open(SmallZoomBake().bake).ok());
  ASSERT_TRUE(engine.SetDimmer(1, Q1_15::FromRaw(0)).ok());  // the zoom spot alone
  // The vertex nearest the point under the zoom spot, (0, 0, 0).
  const std::vector<int32_t>& pos = engine.bake().mesh.positions;
  uint32_t centre = 0;
  int64_t best = INT64_MAX;
  for (uint32_t v = 0; v < engine.vertex_count(); ++v) {
    const int64_t d = int64_t{pos[3 * v]} * pos[3 * v] + int64_t{pos[3 * v + 1]} * pos[3 * v + 1];
    if (d < best) {
      best = d;
      centre = v;
    }
  }
  ASSERT_TRUE(engine.SetZoom(0, Deg(12)).ok());
  engine.Update();
  const std::vector<int32_t> narrow(engine.vertex_luminance().begin(), engine.vertex_luminance().end());
  ASSERT_TRUE(engine.SetZoom(0, Deg(48)).ok());
  engine.Update();
  EXPECT_EQ(engine.last_update_luminaires_recombined(), 1);
  const std::vector<int32_t> wide(engine.vertex_luminance().begin(), engine.vertex_luminance().end());
  EXPECT_GT(narrow[3 * centre], 4 * wide[3 * centre]);  // (48/12)^2 = 16 in peak
  for (int i = 0; i < 20; ++i) {  // zoom up and down, back to 12: no drift
    ASSERT_TRUE(engine.SetZoom(0, Deg(12 + 1.7 * i)).ok());
    engine.Update();
  }
  ASSERT_TRUE(engine.SetZoom(0, Deg(12)).ok());
  engine.Update();
  EXPECT_EQ(std::vector<int32_t>(engine.vertex_luminance().begin(), engine.vertex_luminance().end()), narrow);
}

TEST(Zoom, InBlackCostsNothingUntilLitAndNothingAllocates) {
  Engine engine;
  ASSERT_TRUE(engine.Open(SmallZoomBake().bake).ok());
  ASSERT_TRUE(engine.SetDimmer(0, Q1_15::FromRaw(0)).ok());
  engine.Update();
  g_allocations = 0;
  g_count_allocations = true;
  ASSERT_TRUE(engine.SetZoom(0, Deg(40)).ok());
  engine.Update();
  const int in_black = engine.last_update_luminaires_recombined();
  ASSERT_TRUE(engine.SetDimmer(0, Q1_15::FromRaw(32767)).ok());
  engine.Update();
  const int lit = engine.last_update_luminaires_recombined();
  for (int i = 0; i < 50; ++i) {
    ASSERT_TRUE(engine.SetZoom(0, Deg(10 + 0.8 * i)).ok());
    engine.Update();
  }
  g_count_allocations = false;
  EXPECT_EQ(in_black, 0);
  EXPECT_EQ(lit, 1);
  EXPECT_EQ(g_allocations.load(), 0);
}

// relight-render --set, replay scripts and relightd's fader: NAME.zoom=DEG.
TEST(Zoom, SetTextReachesTheEngine) {
  Engine engine;
  ASSERT_TRUE(engine.Open(SmallZoomBake().bake).ok());
  std::string error;
  ASSERT_TRUE(cli::ApplySetText(engine, "zoom.zoom=17.5", &error)) << error;
  EXPECT_EQ(engine.state(0).zoom_deg.raw(), 17.5 * 65536);
  ASSERT_TRUE(cli::ApplySetText(engine, "zoom.zoom=179", &error)) << error;
  EXPECT_EQ(engine.state(0).zoom_deg.raw(), 50 << 16);  // clamped to the range
  EXPECT_FALSE(cli::ApplySetText(engine, "plain.zoom=20", &error));
  EXPECT_NE(error.find("plain.zoom"), std::string::npos) << error;
  EXPECT_NE(error.find("no zoom"), std::string::npos) << error;
  // An unchanged zoom (a fade's first step reports every parameter) is no change.
  const ParamChange same = ParamChange::Angle(0, static_cast<uint16_t>(engine.FindLuminaire("plain")), Param::kZoom,
                                              Q16_16::FromRaw(0));
  EXPECT_TRUE(cli::ApplyChange(engine, same, &error)) << error;
}

}  // namespace
}  // namespace relight
