#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "relight/hal/param_text.h"
#include "relight/hal/replay_source.h"

namespace relight::hal {
namespace {

// The values of parsed changes in their formats' raw integers.
int32_t Deg(const NamedChange& c) { return c.change.degrees.raw(); }
int32_t Lvl(const NamedChange& c) { return c.change.level.raw(); }

const std::vector<std::string> kFixtures = {"a", "b"};

TEST(ParamText, ParsesEachParameterInItsFormat) {
  NamedChange c[3];
  std::string error;
  ASSERT_EQ(ParseParamText("spot1.pan=30", 7, c, &error), 1) << error;
  EXPECT_EQ(c[0].fixture, "spot1");
  EXPECT_EQ(c[0].change.param, Param::kPan);
  EXPECT_EQ(Deg(c[0]), 30 * 65536);
  EXPECT_EQ(Lvl(c[0]), 0);  // the other member stays 0
  EXPECT_EQ(c[0].change.time_us, 7);
  ASSERT_EQ(ParseParamText("spot1.tilt=-12.5", 0, c, &error), 1);
  EXPECT_EQ(Deg(c[0]), -12 * 65536 - 32768);
  ASSERT_EQ(ParseParamText("a.dimmer=0.5", 0, c, &error), 1);
  EXPECT_EQ(Lvl(c[0]), 16384);  // 0.5 * 32767 rounded
  EXPECT_EQ(Deg(c[0]), 0);
  ASSERT_EQ(ParseParamText("a.dimmer=100%", 0, c, &error), 1);
  EXPECT_EQ(Lvl(c[0]), 32767);
  ASSERT_EQ(ParseParamText("wash-2.colour=1,0.5,0", 0, c, &error), 3);
  EXPECT_EQ(c[0].change.param, Param::kRed);
  EXPECT_EQ(Lvl(c[0]), 32767);
  EXPECT_EQ(c[1].change.param, Param::kGreen);
  EXPECT_EQ(Lvl(c[1]), 16384);
  EXPECT_EQ(c[2].change.param, Param::kBlue);
  EXPECT_EQ(Lvl(c[2]), 0);
  ASSERT_EQ(ParseParamText("spot1.roll=-37.25", 0, c, &error), 1) << error;
  EXPECT_EQ(c[0].change.param, Param::kRoll);
  EXPECT_EQ(Deg(c[0]), -37 * 65536 - 16384);
  EXPECT_TRUE(IsAngle(Param::kRoll));
  EXPECT_STREQ(ParamName(Param::kRoll), "roll");
  ASSERT_EQ(ParseParamText("spot1.zoom=12.5", 0, c, &error), 1) << error;
  EXPECT_EQ(c[0].change.param, Param::kZoom);
  EXPECT_EQ(Deg(c[0]), 12 * 65536 + 32768);
  EXPECT_TRUE(IsAngle(Param::kZoom));
}

TEST(ParamText, AngleRangeErrorsSayWhichParameterAndTheUnit) {
  NamedChange c[3];
  std::string error;
  ASSERT_EQ(ParseParamText("spot1.roll=720", 0, c, &error), 1);  // the end of the range is inside
  for (const char* param : {"pan", "tilt", "roll"}) {
    const std::string text = std::string("spot1.") + param + "=-720.5";
    EXPECT_EQ(ParseParamText(text, 0, c, &error), 0) << text;
    EXPECT_EQ(error, "'" + text + "': " + param + " must be in -720..720 degrees");
  }
  EXPECT_EQ(ParseParamText("spot1.iris=1", 0, c, &error), 0);
  EXPECT_NE(error.find("(pan, tilt, roll, zoom, dimmer, r, g, b, colour; emitters also x, y, size)"), std::string::npos)
      << error;
  for (const char* text : {"spot1.zoom=0", "spot1.zoom=180", "spot1.zoom=-20"}) {
    EXPECT_EQ(ParseParamText(text, 0, c, &error), 0) << text;
    EXPECT_EQ(error, "'" + std::string(text) + "': zoom (the full beam angle) must be in (0, 180) degrees");
  }
  ASSERT_EQ(ParseParamText("spot1.zoom=24.5", 0, c, &error), 1) << error;
  EXPECT_EQ(c[0].change.param, Param::kZoom);
  EXPECT_EQ(Deg(c[0]), 24.5 * 65536);
  EXPECT_TRUE(IsAngle(Param::kZoom));
  EXPECT_STREQ(ParamName(Param::kZoom), "zoom");
}

TEST(ParamText, RejectsBadTextWithAMessage) {
  NamedChange c[3];
  const char* bad[] = {"spot1", "spot1.pan", ".pan=3", "spot1.iris=3", "spot1.zoom=200", "spot1.pan=abc", "spot1.pan=1000",
                       "spot1.dimmer=1.5", "spot1.colour=1,2", "spot1.colour=1,0,0,0", "sp ot.pan=1",
                       "spot1.r=-0.1", "spot1.pan=nan"};
  for (const char* text : bad) {
    std::string error;
    EXPECT_EQ(ParseParamText(text, 0, c, &error), 0) << text;
    EXPECT_NE(error.find(text), std::string::npos) << "message should quote the input: " << error;
  }
}

TEST(ReplayScript, ParsesTimedChangesInOrder) {
  std::vector<ParamChange> changes;
  const std::string text =
      "# a show\n"
      "0     a.dimmer=1   b.pan=10\n"
      "\n"
      "0.5   b.pan=20 # half a second in\n"
      "2     b.colour=1,0,0\n"
      "2.25  b.roll=90\n";
  ASSERT_TRUE(ParseReplayScript(text, "show.replay", kFixtures, &changes).ok());
  ASSERT_EQ(changes.size(), 7u);
  EXPECT_EQ(changes[0].fixture, 0);  // names resolved to indices in the list, once
  EXPECT_EQ(changes[1].fixture, 1);
  EXPECT_EQ(changes[6].time_us, 2250000);
  EXPECT_EQ(changes[6].param, Param::kRoll);
  EXPECT_EQ(changes[6].degrees.raw(), 90 * 65536);
  EXPECT_EQ(changes[2].time_us, 500000);
  EXPECT_EQ(changes[2].degrees.raw(), 20 * 65536);
  EXPECT_EQ(changes[5].time_us, 2000000);
  EXPECT_EQ(changes[5].param, Param::kBlue);
  EXPECT_EQ(changes[5].fixture, 1);
}

TEST(ReplayScript, AFixtureTheListLacksIsAnErrorAtLoad) {
  std::vector<ParamChange> changes;
  const Status st = ParseReplayScript("0 a.pan=1\n1 c.tilt=2\n", "show.replay", kFixtures, &changes);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("show.replay:2: no fixture 'c' (there are: a, b)"), std::string::npos) << st.message();
}

TEST(ReplayScript, ErrorsNameFileAndLine) {
  std::vector<ParamChange> changes;
  Status st = ParseReplayScript("0 a.pan=1\n1 b.tilt=x\n", "show.replay", kFixtures, &changes);
  EXPECT_FALSE(st.ok());
  EXPECT_NE(st.message().find("show.replay:2:"), std::string::npos) << st.message();
  st = ParseReplayScript("1 a.pan=1\n0.5 a.pan=2\n", "s", kFixtures, &changes);
  EXPECT_NE(st.message().find("s:2:"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("backwards"), std::string::npos) << st.message();
  st = ParseReplayScript("soon a.pan=1\n", "s", kFixtures, &changes);
  EXPECT_NE(st.message().find("s:1:"), std::string::npos) << st.message();
  st = ParseReplayScript("3\n", "s", kFixtures, &changes);
  EXPECT_FALSE(st.ok());
  st = ParseReplayScript("0 a.pan=1\n1 a.roll=900\n", "s", kFixtures, &changes);
  EXPECT_NE(st.message().find("s:2:"), std::string::npos) << st.message();
  EXPECT_NE(st.message().find("roll must be in -720..720 degrees"), std::string::npos) << st.message();
}

// Issue 17: a line a megabyte long is refused by its length, at once.
TEST(ReplayScript, OverlongLineIsAnErrorNamingItsLength) {
  std::vector<ParamChange> changes;
  std::string line = "0";
  while (line.size() < (1u << 20)) line += " a.pan=1";
  const Status st = ParseReplayScript("0 a.pan=1\n" + line + "\n", "show.replay", kFixtures, &changes);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("show.replay:2: line is 1048577 bytes, more than the limit of 4096"),
            std::string::npos)
      << st.message();
  // At the limit it still reads.
  line = "0 a.pan=1";
  while (line.size() + 8 <= kMaxReplayLineBytes) line += " a.pan=1";
  EXPECT_TRUE(ParseReplayScript(line + "\n", "s", kFixtures, &changes).ok());
}

TEST(ReplaySource, PollsDueChangesAndKeepsTheRestQueued) {
  const std::string path = ::testing::TempDir() + "/replay_source_test.replay";
  {
    std::ofstream f(path);
    f << "0 a.pan=1 a.tilt=2 a.dimmer=0.25\n1 a.pan=3\n";
  }
  ReplaySource source(path, kFixtures);
  ASSERT_TRUE(source.Start().ok());
  EXPECT_EQ(source.duration_us(), 1000000);
  ParamChange out[2];
  EXPECT_EQ(source.Poll(0, out, 2), 2u);  // capacity bound: third stays queued
  EXPECT_EQ(out[1].param, Param::kTilt);
  EXPECT_EQ(source.Poll(0, out, 2), 1u);
  EXPECT_EQ(out[0].param, Param::kDimmer);
  EXPECT_EQ(source.Poll(999999, out, 2), 0u);
  EXPECT_FALSE(source.Finished());
  EXPECT_EQ(source.Poll(1000000, out, 2), 1u);
  EXPECT_EQ(out[0].degrees.raw(), 3 * 65536);
  EXPECT_TRUE(source.Finished());
  std::remove(path.c_str());
}

TEST(ReplaySource, MissingFileIsNotFoundAtStart) {
  ReplaySource source("/nonexistent/show.replay", kFixtures);
  const Status st = source.Start();
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("/nonexistent/show.replay"), std::string::npos);
}

}  // namespace
}  // namespace relight::hal
