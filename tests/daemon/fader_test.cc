#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "relight/control/fader.h"

namespace relight::control {
using hal::DimmerCurve;
using hal::FixturePatch;
namespace {

std::vector<FixturePatch> Fixtures(int32_t fade_ms, DimmerCurve curve) {
  FixturePatch f;
  f.name = "spot";
  f.fade_ms = fade_ms;
  f.dimmer_curve = curve;
  f.modbus_base = 0;
  return {f};
}

// A target for slot 0 ("spot"), `value` the raw integer of the parameter's format.
ParamChange Target(Param param, int32_t value) {
  return IsAngle(param) ? ParamChange::Angle(0, 0, param, Q16_16::FromRaw(value))
                        : ParamChange::Level(0, 0, param, Q1_15::FromRaw(static_cast<int16_t>(value)));
}

int32_t Raw(const ParamChange& c) { return IsAngle(c.param) ? c.degrees.raw() : c.level.raw(); }

FixtureState Dark() {
  FixtureState s{};
  return s;
}

// The value of `param` among the changes, or `fallback` if none.
int32_t Find(const ParamChange* out, size_t n, Param param, int32_t fallback) {
  for (size_t i = 0; i < n; ++i) {
    if (out[i].param == param) return Raw(out[i]);
  }
  return fallback;
}

TEST(Fader, ResetReportsEveryParameterOnce) {
  Fader fader(Fixtures(0, DimmerCurve::kLinear));
  fader.Reset(0, Dark());
  ParamChange out[kParamCount];
  // A luminaire's parameters, not an emitter's x, y and size.
  const size_t n = fader.Step(0, out);
  EXPECT_EQ(n, static_cast<size_t>(kFixtureParamCount));
  for (size_t i = 0; i < n; ++i) EXPECT_LT(static_cast<int>(out[i].param), kFixtureParamCount);
  EXPECT_EQ(fader.Step(1, out), 0u);
}

// An emitter's slot (issue 15) reports its seven: dimmer, colour, x, y, size,
// and fades x like a level.
TEST(Fader, AnEmitterSlotReportsItsLevelsAndFadesThem) {
  Fader fader(Fixtures(1000, DimmerCurve::kLinear));
  int32_t values[kParamCount] = {};
  values[static_cast<int>(Param::kX)] = 8192;
  values[static_cast<int>(Param::kDimmer)] = 32767;
  fader.ResetValues(0, values, /*emitter=*/true);
  ParamChange out[kParamCount];
  const size_t n = fader.Step(0, out);
  EXPECT_EQ(n, 7u);
  for (size_t i = 0; i < n; ++i) EXPECT_TRUE(IsEmitterParam(out[i].param)) << ParamName(out[i].param);
  EXPECT_EQ(Find(out, n, Param::kX, -1), 8192);
  ASSERT_TRUE(fader.SetTarget(Target(Param::kX, 24576), 0));
  ASSERT_EQ(fader.Step(500000, out), 1u);
  EXPECT_EQ(out[0].param, Param::kX);
  EXPECT_EQ(out[0].level.raw(), 16384);  // half way
}

TEST(Fader, ZoomFadesInDegrees) {
  Fader fader(Fixtures(1000, DimmerCurve::kLinear));
  FixtureState start = Dark();
  start.zoom_deg = Q16_16::FromInt(20);
  fader.Reset(0, start);
  ParamChange out[kParamCount];
  EXPECT_EQ(Find(out, fader.Step(0, out), Param::kZoom, -1), 20 << 16);
  ASSERT_TRUE(fader.SetTarget(Target(Param::kZoom, 40 << 16), 0));
  const size_t n = fader.Step(500000, out);
  ASSERT_EQ(n, 1u);
  EXPECT_EQ(out[0].param, Param::kZoom);
  EXPECT_EQ(out[0].degrees.raw(), 30 << 16);  // half way
  EXPECT_EQ(out[0].fixture, 0);
}

TEST(Fader, ChangesAreTypedByTheirParameter) {
  Fader fader(Fixtures(0, DimmerCurve::kLinear));
  fader.Reset(0, Dark());
  ParamChange out[kParamCount];
  (void)fader.Step(0, out);
  ASSERT_TRUE(fader.SetTarget(Target(Param::kTilt, -(7 << 16)), 1));
  ASSERT_TRUE(fader.SetTarget(Target(Param::kGreen, 1234), 1));
  ASSERT_EQ(fader.Step(1, out), 2u);
  EXPECT_EQ(out[0].param, Param::kTilt);
  EXPECT_EQ(out[0].degrees.raw(), -(7 << 16));
  EXPECT_EQ(out[0].level.raw(), 0);
  EXPECT_EQ(out[1].param, Param::kGreen);
  EXPECT_EQ(out[1].level.raw(), 1234);
  EXPECT_EQ(out[1].degrees.raw(), 0);
}

TEST(Fader, ZeroFadeJumps) {
  Fader fader(Fixtures(0, DimmerCurve::kLinear));
  fader.Reset(0, Dark());
  ParamChange out[kParamCount];
  (void)fader.Step(0, out);
  ASSERT_TRUE(fader.SetTarget(Target(Param::kPan, 90 << 16), 1000));
  ASSERT_EQ(fader.Step(1000, out), 1u);
  EXPECT_EQ(Raw(out[0]), 90 << 16);
  EXPECT_TRUE(fader.Idle(1000));
  ParamChange no_slot = Target(Param::kPan, 0);
  no_slot.fixture = 1;  // one slot only
  EXPECT_FALSE(fader.SetTarget(no_slot, 0));
}

TEST(Fader, LinearRampInIntegerTime) {
  Fader fader(Fixtures(1000, DimmerCurve::kLinear));  // 1 s fade
  fader.Reset(0, Dark());
  ParamChange out[kParamCount];
  (void)fader.Step(0, out);
  ASSERT_TRUE(fader.SetTarget(Target(Param::kPan, 100 << 16), 2000000));
  for (int64_t t = 2000000; t <= 3000000; t += 125000) {
    const size_t n = fader.Step(t, out);
    const double ref = 100.0 * 65536.0 * static_cast<double>(t - 2000000) / 1e6;
    const int32_t got = Find(out, n, Param::kPan, -1);
    if (t == 2000000) {
      EXPECT_EQ(n, 0u);  // nothing has moved yet
      continue;
    }
    EXPECT_LE(std::fabs(got - ref), 1.0) << t;  // truncation: < 1 LSB
  }
  EXPECT_TRUE(fader.Idle(3000000));
  // Retargeting mid-ramp starts from the value shown, not from the old start.
  ASSERT_TRUE(fader.SetTarget(Target(Param::kPan, 0), 4000000));
  const size_t n = fader.Step(4500000, out);
  EXPECT_EQ(Find(out, n, Param::kPan, -1), 50 << 16);
}

TEST(Fader, RollRampsInDegreesLikePanAndTilt) {
  Fader fader(Fixtures(400, DimmerCurve::kSquare));  // the curve is for the dimmer only
  FixtureState start = Dark();
  start.roll_deg = Q16_16::FromInt(-30);
  fader.Reset(0, start);
  ParamChange out[kParamCount];
  const size_t first = fader.Step(0, out);
  EXPECT_EQ(Find(out, first, Param::kRoll, 0), -(30 << 16));  // reset reports the roll too
  ASSERT_TRUE(fader.SetTarget(Target(Param::kRoll, 90 << 16), 1000));
  const size_t n = fader.Step(1000 + 100000, out);  // a quarter of the way: -30 + 120 / 4
  ASSERT_EQ(n, 1u);
  EXPECT_EQ(out[0].param, Param::kRoll);
  EXPECT_EQ(Raw(out[0]), 0);
  EXPECT_FALSE(fader.Idle(1000 + 100000));
  EXPECT_EQ(Find(out, fader.Step(1000 + 400000, out), Param::kRoll, -1), 90 << 16);
  EXPECT_TRUE(fader.Idle(1000 + 400000));
}

TEST(Fader, SquareLawDimmerCurve) {
  EXPECT_EQ(ApplyDimmerCurve(DimmerCurve::kSquare, 32767), 32767);
  EXPECT_EQ(ApplyDimmerCurve(DimmerCurve::kSquare, 0), 0);
  EXPECT_EQ(ApplyDimmerCurve(DimmerCurve::kSquare, 16384), 8192);  // (1/2)^2
  EXPECT_EQ(ApplyDimmerCurve(DimmerCurve::kLinear, 12345), 12345);
  for (int v = 0; v <= 32767; v += 13) {
    const double ref = (v / 32767.0) * (v / 32767.0) * 32767.0;
    EXPECT_LE(std::fabs(ApplyDimmerCurve(DimmerCurve::kSquare, v) - ref), 0.5) << v;
  }
  Fader fader(Fixtures(0, DimmerCurve::kSquare));
  fader.Reset(0, Dark());
  ParamChange out[kParamCount];
  (void)fader.Step(0, out);
  ASSERT_TRUE(fader.SetTarget(Target(Param::kDimmer, 16384), 10));
  ASSERT_EQ(fader.Step(10, out), 1u);
  EXPECT_EQ(Raw(out[0]), 8192);
}

}  // namespace
}  // namespace relight::control
