// The DMX replay (recorded frames) and the change logic it shares with the
// OLA source: recordings parse with file:line errors; played through a DMX
// patch they yield typed changes for what changed, in the engine's formats,
// exactly as the personality decodes them; loss of signal and the shutter
// act on the dimmer.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "relight/base/console_value.h"
#include "relight/hal/dmx/dmx_replay_source.h"

namespace relight::hal {
namespace {

// spot (relight-test-spot, "16 bit": dimmer, dimmer fine, pan, pan fine,
// tilt, tilt fine, C, M, Y, wheel, zoom, shutter, gobo) at universe 1
// address 10; an RGBW par at 30.
DmxPatch TestPatch(const std::string& dmx_section = "") {
  DmxPatch patch;
  const std::string where = std::string(RELIGHT_SOURCE_DIR) + "/fixtures/dmx/replay_test.patch.toml";
  const Status st = ParseDmxPatch(
      dmx_section +
          "[[dmx_fixture]]\nname = \"spot\"\ntype = \"relight-test-spot.toml\"\nmode = \"16 bit\"\nuniverse = 1\n"
          "address = 10\n[[dmx_fixture]]\nname = \"par\"\ntype = \"relight-test-rgbw.toml\"\nmode = \"4 channel\"\n"
          "universe = 1\naddress = 30\n",
      where, &patch);
  EXPECT_TRUE(st.ok()) << st.message();
  return patch;
}

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::vector<ParamChange> PollAll(InputSource& source, int64_t now_us) {
  std::vector<ParamChange> out(64);
  out.resize(source.Poll(now_us, out.data(), out.size()));
  return out;
}

const ParamChange* Find(const std::vector<ParamChange>& changes, uint16_t fixture, Param param) {
  for (const ParamChange& c : changes) {
    if (c.fixture == fixture && c.param == param) return &c;
  }
  return nullptr;
}

TEST(DmxRecording, ParsesFramesRunsAndComments) {
  DmxRecording rec;
  const Status st = ParseDmxRecording(
      "# a show\n0 1 1=ff00 10=12\n\n22727 2 512=7f # the last slot\n22727 1 3=AbCd\n", "show.dmxrec", &rec);
  ASSERT_TRUE(st.ok()) << st.message();
  ASSERT_EQ(rec.frames.size(), 3u);
  EXPECT_EQ(rec.frames[1].time_us, 22727);
  EXPECT_EQ(rec.frames[1].universe, 2u);
  ASSERT_EQ(rec.frames[0].run_count, 2u);
  EXPECT_EQ(rec.runs[1].slot, 10);
  EXPECT_EQ(rec.runs[1].count, 1);
  EXPECT_EQ(rec.bytes[rec.runs[1].offset], 0x12);
  const DmxReplayRun& last = rec.runs[rec.frames[2].first_run];
  EXPECT_EQ(last.count, 2);
  EXPECT_EQ(rec.bytes[last.offset], 0xAB);
  EXPECT_EQ(rec.bytes[last.offset + 1], 0xCD);
}

TEST(DmxRecording, ErrorsNameFileAndLine) {
  const struct {
    const char* text;
    const char* where;
    const char* what;
  } cases[] = {
      {"0 1 1=00\nsoon 1 1=00\n", "s:2:", "expected a time in microseconds"},
      {"5 1 1=00\n4 1 1=00\n", "s:2:", "goes backwards"},
      {"0 1 1=00\n0\n", "s:2:", "expected a universe"},
      {"0 x 1=00\n", "s:1:", "expected a universe"},
      {"0 1\n", "s:1:", "at least one SLOT=HEX"},
      {"0 1 0=00\n", "s:1:", "SLOT in 1..512"},
      {"0 1 513=00\n", "s:1:", "SLOT in 1..512"},
      {"0 1 1=0\n", "s:1:", "even number of hex digits"},
      {"0 1 1=zz\n", "s:1:", "is not hex"},
      {"0 1 511=000000\n", "s:1:", "pass slot 512"},
      {"0 1 1-00\n", "s:1:", "expected SLOT=HEX"},
      {"-1 1 1=00\n", "s:1:", "expected a time"},
  };
  for (const auto& c : cases) {
    DmxRecording rec;
    const Status st = ParseDmxRecording(c.text, "s", &rec);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << c.text;
    EXPECT_NE(st.message().find(c.where), std::string::npos) << c.text << " -> " << st.message();
    EXPECT_NE(st.message().find(c.what), std::string::npos) << c.text << " -> " << st.message();
  }
  DmxRecording rec;
  const Status st = ParseDmxRecording("0 1 1=" + std::string(kMaxDmxReplayLineBytes, 'a') + "\n", "s", &rec);
  EXPECT_NE(st.message().find("s:1: line is"), std::string::npos) << st.message();
}

TEST(DmxReplaySource, PlaysFramesAsTypedChangesOfWhatChanged) {
  // spot: dimmer 0x1234, pan 0xABCD, tilt 0x01FF, C 255 M 0 Y 128, wheel 0,
  // zoom 255, shutter 255 (open); par: R 255 G 0 B 64 W 0.
  const std::string path = WriteTemp("play.dmxrec",
                                     "0 1 10=1234abcd01ffff0080 19=00ffff00 30=ff004000\n"
                                     "1000 2 10=ffff       # another universe: not patched, ignored\n"
                                     "2000 1 13=ce\n"       // pan fine only
                                     "3000 1 20=00\n");     // zoom to its narrowest
  DmxReplaySource source(TestPatch(), path);
  ASSERT_TRUE(source.Start().ok());
  EXPECT_EQ(source.duration_us(), 3000);
  EXPECT_TRUE(PollAll(source, -1).empty());  // nothing before the first frame: the bake's look stays

  const std::vector<ParamChange> first = PollAll(source, 0);
  // The first frame reports everything: spot's dimmer, pan, tilt, r, g, b, zoom; the par's dimmer (full: it
  // has no dimmer channel), r, g, b (no pan or tilt channel: the bake's aim stays).
  EXPECT_EQ(first.size(), 11u);
  EXPECT_EQ(Find(first, 1, Param::kPan), nullptr);
  ASSERT_NE(Find(first, 0, Param::kDimmer), nullptr);
  EXPECT_EQ(Find(first, 0, Param::kDimmer)->level.raw(), (0x1234 * 32767 + 32767) / 65535);
  EXPECT_EQ(Find(first, 0, Param::kPan)->degrees, ConsoleToDegrees(0xABCD, 540 << 16));  // the type's 540 deg
  EXPECT_EQ(Find(first, 0, Param::kTilt)->degrees, ConsoleToDegrees(0x01FF, 270 << 16));
  EXPECT_EQ(Find(first, 0, Param::kRed)->level.raw(), 0);  // full cyan
  EXPECT_EQ(Find(first, 0, Param::kGreen)->level.raw(), 32767);
  EXPECT_EQ(Find(first, 0, Param::kBlue)->level.raw(), 32767 - (128 * 257 * 32767 + 32767) / 65535);
  EXPECT_EQ(Find(first, 0, Param::kZoom)->degrees.raw(), 40 << 16);
  EXPECT_EQ(Find(first, 0, Param::kDimmer)->time_us, 0);
  EXPECT_EQ(Find(first, 1, Param::kRed)->level.raw(), 32767);
  EXPECT_EQ(Find(first, 1, Param::kGreen)->level.raw(), 0);
  EXPECT_EQ(Find(first, 1, Param::kBlue)->level.raw(), (64 * 257 * 32767 + 32767) / 65535);
  EXPECT_EQ(Find(first, 1, Param::kZoom), nullptr);  // a fixed 25 deg lens: no zoom channel, nothing to report

  EXPECT_TRUE(PollAll(source, 1000).empty());  // universe 2 only
  const std::vector<ParamChange> pan = PollAll(source, 2000);
  ASSERT_EQ(pan.size(), 1u);  // only what changed; slots not listed kept their values
  EXPECT_EQ(pan[0].fixture, 0);
  EXPECT_EQ(pan[0].param, Param::kPan);
  EXPECT_EQ(pan[0].degrees, ConsoleToDegrees(0xABCE, 540 << 16));
  EXPECT_EQ(pan[0].time_us, 2000);
  EXPECT_FALSE(source.Finished());
  const std::vector<ParamChange> zoom = PollAll(source, 5000);
  ASSERT_EQ(zoom.size(), 1u);
  EXPECT_EQ(zoom[0].param, Param::kZoom);
  EXPECT_EQ(zoom[0].degrees.raw(), 10 << 16);
  EXPECT_TRUE(source.Finished());
  std::remove(path.c_str());
}

TEST(DmxReplaySource, ShutterAndLossOfSignalActOnTheDimmer) {
  // Shutter closed (0..7) darkens whatever the dimmer says.
  const std::string path = WriteTemp("loss.dmxrec",
                                     "0 1 10=ffff 21=ff\n"
                                     "1000 1 21=03\n"
                                     "2000 1 21=ff\n");
  {
    DmxReplaySource hold(TestPatch("[dmx]\nloss_timeout_ms = 100\n"), path);
    ASSERT_TRUE(hold.Start().ok());
    EXPECT_EQ(Find(PollAll(hold, 0), 0, Param::kDimmer)->level.raw(), 32767);
    const std::vector<ParamChange> closed = PollAll(hold, 1000);
    ASSERT_EQ(closed.size(), 1u);
    EXPECT_EQ(closed[0].level.raw(), 0);
    EXPECT_EQ(Find(PollAll(hold, 2000), 0, Param::kDimmer)->level.raw(), 32767);
    EXPECT_TRUE(PollAll(hold, 10'000'000).empty());  // "hold": the look stays when frames stop
  }
  DmxReplaySource blackout(TestPatch("[dmx]\nloss_of_signal = \"blackout\"\nloss_timeout_ms = 100\n"), path);
  ASSERT_TRUE(blackout.Start().ok());
  (void)PollAll(blackout, 2000);
  EXPECT_TRUE(PollAll(blackout, 2000 + 100'000).empty());  // at the timeout: not yet lost
  const std::vector<ParamChange> lost = PollAll(blackout, 2000 + 100'001);
  ASSERT_EQ(lost.size(), 1u);  // the spot's; no frame reached the par's slots (30..33), so it had nothing
  EXPECT_EQ(lost[0].param, Param::kDimmer);
  EXPECT_EQ(lost[0].level.raw(), 0);
  EXPECT_TRUE(PollAll(blackout, 3'000'000).empty());
  std::remove(path.c_str());
}

// "fade": once the signal counts as lost, the dimmer goes from its last value
// to 0 in loss_fade_ms, linearly, then stays there.
TEST(DmxReplaySource, LossOfSignalCanFadeOut) {
  const std::string path = WriteTemp("fade.dmxrec", "0 1 10=ffff 21=ff\n2000 1 10=8000\n");
  DmxReplaySource fade(TestPatch("[dmx]\nloss_of_signal = \"fade\"\nloss_timeout_ms = 100\nloss_fade_ms = 1000\n"),
                       path);
  ASSERT_TRUE(fade.Start().ok());
  const std::vector<ParamChange> last = PollAll(fade, 2000);
  const ParamChange* start = Find(last, 0, Param::kDimmer);
  ASSERT_NE(start, nullptr);
  const int32_t full = start->level.raw();  // 16-bit 0x8000: about half
  EXPECT_NEAR(full, 16384, 1);
  EXPECT_TRUE(PollAll(fade, 2000 + 100'000).empty());  // at the timeout: not yet lost
  const auto dimmer_at = [&](int64_t t) {
    const std::vector<ParamChange> c = PollAll(fade, t);
    const ParamChange* d = Find(c, 0, Param::kDimmer);
    return d == nullptr ? -1 : int32_t{d->level.raw()};
  };
  EXPECT_EQ(dimmer_at(2000 + 100'000 + 250'000), full * 3 / 4);
  EXPECT_EQ(dimmer_at(2000 + 100'000 + 500'000), full / 2);
  EXPECT_EQ(dimmer_at(2000 + 100'000 + 999'000), (full * 32) >> 15);  // 1 ms of 1000 left
  EXPECT_EQ(dimmer_at(2000 + 100'000 + 1'000'000), 0);
  EXPECT_TRUE(PollAll(fade, 5'000'000).empty()) << "faded out: nothing more to say";
  std::remove(path.c_str());
}

TEST(DmxReplaySource, StartErrorsNameTheFile) {
  DmxReplaySource missing(TestPatch(), "/nonexistent/show.dmxrec");
  const Status st = missing.Start();
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("/nonexistent/show.dmxrec"), std::string::npos);
  const std::string path = WriteTemp("bad.dmxrec", "0 1 1=00\n\n7 1 1=0g\n");
  DmxReplaySource bad(TestPatch(), path);
  const Status parse = bad.Start();
  EXPECT_NE(parse.message().find(path + ":3:"), std::string::npos) << parse.message();
  std::remove(path.c_str());
}

}  // namespace
}  // namespace relight::hal
