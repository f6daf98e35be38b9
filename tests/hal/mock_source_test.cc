#include <gtest/gtest.h>

#include <vector>

#include "hal_test_support.h"
#include "relight/hal/mock_source.h"

namespace relight::hal {
namespace {

using testing::MapOf;
using testing::RestRegisters;

Patch GpioPatch() {
  Patch p;
  const Status st = ParsePatch(R"(
[[fixture]]
name = "spot"
[[fixture]]
name = "wash"
[[gpio_button]]
chip = "gpiochip0"
line = 17
fixture = "spot"
on_level = 0.75
debounce_ms = 20
[[gpio_button]]
chip = "gpiochip0"
line = 18
action = "preset"
preset = ["wash.pan=45", "wash.dimmer=0.5"]
[[gpio_encoder]]
chip = "gpiochip0"
line_a = 22
line_b = 23
fixture = "wash"
param = "dimmer"
step = 0.125
start = 0.5
)",
                               "gpio.toml", &p);
  EXPECT_TRUE(st.ok()) << st.ToString();
  EXPECT_TRUE(ResolvePatch({{"spot"}, {"wash"}}, &p).ok());
  return p;
}

std::vector<ParamChange> PollAll(MockSource& mock, int64_t now_us) {
  std::vector<ParamChange> all(64);
  all.resize(mock.Poll(now_us, all.data(), all.size()));
  return all;
}

TEST(MockSource, HoldingRegistersDecodeAsTheServerWould) {
  const Patch patch = GpioPatch();
  const RegisterMap map = MapOf(patch);
  MockSource mock(patch, RestRegisters(map));
  ASSERT_TRUE(mock.Start().ok());
  EXPECT_EQ(mock.SetHoldingRegister(kRegPan, 65535, 100), 0);
  EXPECT_EQ(mock.SetHoldingRegister(kRegRed, 256, 100), kExceptionIllegalValue);
  EXPECT_EQ(mock.SetHoldingRegister(99, 0, 100), kExceptionIllegalAddress);
  EXPECT_EQ(mock.holding_register(kRegRed), 0);  // a refused write changes nothing
  const std::vector<ParamChange> got = PollAll(mock, 200);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].fixture, testing::FixtureIndexOf("spot"));
  EXPECT_EQ(got[0].param, Param::kPan);
  EXPECT_EQ(testing::Raw(got[0]), AngleQ16FromRegister(65535, 540 << 16));
  EXPECT_EQ(got[0].time_us, 100);
}

TEST(MockSource, ButtonDebounceTogglesOncePerPress) {
  MockSource mock(GpioPatch());
  // Bouncing press (active low): 0 at 1000, 1 at 1500, 0 at 2000 us, then held.
  ASSERT_TRUE(mock.SetLine("gpiochip0", 17, false, 1000).ok());
  ASSERT_TRUE(mock.SetLine("gpiochip0", 17, true, 1500).ok());
  ASSERT_TRUE(mock.SetLine("gpiochip0", 17, false, 2000).ok());
  EXPECT_TRUE(PollAll(mock, 21000).empty());  // 19 ms stable: not yet
  std::vector<ParamChange> got = PollAll(mock, 22000);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].param, Param::kDimmer);
  EXPECT_EQ(testing::Raw(got[0]), 24575);  // on_level 0.75
  EXPECT_EQ(got[0].time_us, 22000);
  // A 5 ms glitch on release is ignored; the real release and next press switch off.
  ASSERT_TRUE(mock.SetLine("gpiochip0", 17, true, 100000).ok());
  ASSERT_TRUE(mock.SetLine("gpiochip0", 17, false, 105000).ok());
  EXPECT_TRUE(PollAll(mock, 200000).empty());
  ASSERT_TRUE(mock.SetLine("gpiochip0", 17, true, 300000).ok());
  ASSERT_TRUE(mock.SetLine("gpiochip0", 17, false, 400000).ok());
  got = PollAll(mock, 500000);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(testing::Raw(got[0]), 0);
}

TEST(MockSource, PresetButtonRecallsItsChanges) {
  MockSource mock(GpioPatch());
  ASSERT_TRUE(mock.SetLine("gpiochip0", 18, false, 0).ok());
  const std::vector<ParamChange> got = PollAll(mock, 50000);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].fixture, testing::FixtureIndexOf("wash"));
  EXPECT_EQ(got[0].param, Param::kPan);
  EXPECT_EQ(testing::Raw(got[0]), 45 << 16);
  EXPECT_EQ(got[1].param, Param::kDimmer);
}

// One detent clockwise: A leads B through 00 -> 01 -> 11 -> 10 -> 00 (A is bit 1).
void Turn(MockSource& mock, int counts, int64_t* t_us) {
  static const bool kA[4] = {false, false, true, true};
  static const bool kB[4] = {false, true, true, false};
  static int phase = 0;
  for (int i = 0; i < (counts < 0 ? -counts : counts); ++i) {
    const int next = (phase + (counts > 0 ? 1 : 3)) % 4;
    if (kA[next] != kA[phase]) {
      ASSERT_TRUE(mock.SetLine("gpiochip0", 22, kA[next], (*t_us)++).ok());
    }
    if (kB[next] != kB[phase]) {
      ASSERT_TRUE(mock.SetLine("gpiochip0", 23, kB[next], (*t_us)++).ok());
    }
    phase = next;
  }
}

TEST(MockSource, EncoderQuadratureMovesTheDimmerAndClamps) {
  MockSource mock(GpioPatch());
  int64_t t = 10;
  Turn(mock, 2, &t);  // +2 counts of 0.125 from 0.5
  std::vector<ParamChange> got = PollAll(mock, t);
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(testing::Raw(got[1]), 16384 + 2 * 4096);
  Turn(mock, -1, &t);
  got = PollAll(mock, t);
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(testing::Raw(got[0]), 16384 + 4096);
  Turn(mock, 20, &t);  // past full: clamps at 1.0 and stops reporting
  got = PollAll(mock, t);
  EXPECT_EQ(testing::Raw(got.back()), 32767);
  EXPECT_LE(got.size(), 4u);
  // Down to 0 (clamped), then 3 counts up, which leaves both lines low (phase 00).
  Turn(mock, -20, &t);
  Turn(mock, 3, &t);
  got = PollAll(mock, t);
  EXPECT_EQ(testing::Raw(got.back()), 3 * 4096);
  // Contact bounce on B (up, down, up): +1 -1 +1 nets one count.
  ASSERT_TRUE(mock.SetLine("gpiochip0", 23, true, t++).ok());
  ASSERT_TRUE(mock.SetLine("gpiochip0", 23, false, t++).ok());
  ASSERT_TRUE(mock.SetLine("gpiochip0", 23, true, t++).ok());
  got = PollAll(mock, t);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(testing::Raw(got.back()), 4 * 4096);
}

// Zoom on an encoder (issue 12): steps in degrees of beam angle from the
// patch's start, kept inside (0, 180) (the engine clamps to the bake's range).
TEST(MockSource, AZoomEncoderStepsTheBeamAngleFromItsStart) {
  Patch p;
  ASSERT_TRUE(ParsePatch("[[fixture]]\nname = \"spot\"\n[[gpio_encoder]]\nchip = \"gpiochip0\"\nline_a = 22\n"
                         "line_b = 23\nfixture = \"spot\"\nparam = \"zoom\"\nstep = 0.5\nstart = 24\n",
                         "zoom.toml", &p)
                  .ok());
  ASSERT_TRUE(ResolvePatch({{"spot"}}, &p).ok());
  MockSource mock(p);
  int64_t t = 10;
  // Quadrature from 00 (this test's own phase: Turn()'s is shared with the tests before it).
  int phase = 0;
  const auto turn = [&](int counts) {
    static const bool kA[4] = {false, false, true, true};
    static const bool kB[4] = {false, true, true, false};
    for (int i = 0; i < (counts < 0 ? -counts : counts); ++i) {
      const int next = (phase + (counts > 0 ? 1 : 3)) % 4;
      if (kA[next] != kA[phase]) {
        ASSERT_TRUE(mock.SetLine("gpiochip0", 22, kA[next], t++).ok());
      }
      if (kB[next] != kB[phase]) {
        ASSERT_TRUE(mock.SetLine("gpiochip0", 23, kB[next], t++).ok());
      }
      phase = next;
    }
  };
  turn(3);
  std::vector<ParamChange> got = PollAll(mock, t);
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got.back().param, Param::kZoom);
  EXPECT_EQ(testing::Raw(got.back()), (24 << 16) + 3 * (1 << 15));  // 25.5 degrees
  turn(-60);  // 24 + 1.5 - 30 degrees: stops just above 0
  got = PollAll(mock, t);
  EXPECT_EQ(testing::Raw(got.back()), 655);
  EXPECT_GT(testing::Raw(got.back()), 0);
}

TEST(MockSource, InjectedChangesComeDueInTimeAndTheQueueIsBounded) {
  MockSource mock(GpioPatch());
  ParamChange c = ParamChange::Level(500, testing::FixtureIndexOf("spot"), Param::kDimmer, Q1_15::FromRaw(100));
  mock.Inject(c);
  EXPECT_TRUE(PollAll(mock, 499).empty());
  EXPECT_EQ(PollAll(mock, 500).size(), 1u);
  for (size_t i = 0; i < MockSource::kQueueCapacity + 10; ++i) mock.Inject(c);
  EXPECT_EQ(mock.dropped(), 10u);
  EXPECT_EQ(mock.SetLine("gpiochip9", 1, true, 0).code(), StatusCode::kNotFound);
}

TEST(MockSource, RecordsStartsPollsFramesAndFailures) {
  MockSource mock(GpioPatch());
  mock.FailStartWith(Status(StatusCode::kNotFound, "no such console"));
  EXPECT_EQ(mock.Start().code(), StatusCode::kNotFound);
  mock.OnFrameOut(7, 1234);
  (void)PollAll(mock, 0);
  mock.Stop();
  EXPECT_EQ(mock.start_count(), 1);
  EXPECT_EQ(mock.poll_count(), 1);
  EXPECT_EQ(mock.stop_count(), 1);
  EXPECT_EQ(mock.last_frame(), 7u);
  EXPECT_EQ(mock.last_latency_us(), 1234u);
}

}  // namespace
}  // namespace relight::hal
