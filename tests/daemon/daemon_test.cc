// relightd's core driven in-process: replay determinism, the mock driving
// the engine through the patch, fades and curves, patch reload, sinks.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <cstring>

#include "daemon_test_support.h"
#include "relight/base/clock.h"
#include "relight/hal/mock_source.h"
#include "relight/hal/register_map.h"
#include "relight/hal/patch.h"

namespace relight::daemon {
namespace {

using testing::ReadAll;
using testing::RunToEnd;
using testing::SmallConfig;
using testing::WriteTemp;

const char* kScript =
    "0.0  spot.dimmer=0.8  spot.pan=0  spot.tilt=10\n"
    "0.25 spot.tilt=35  spot.colour=1,0.5,0.2\n"
    "0.5  spot.pan=90   spot.dimmer=0.3\n";

std::string RenderReplayToPpm(bool script_time, const std::string& name, DaemonStats* stats) {
  DaemonConfig c = SmallConfig();
  // A script file per run: tests of this binary run in parallel processes under ctest -j and
  // would otherwise truncate each other's script mid-read.
  c.replay_path = WriteTemp(name + ".replay", kScript);
  c.script_time = script_time;
  c.exit_when_replay_done = true;
  Daemon d;
  EXPECT_TRUE(d.Open(c).ok());
  std::unique_ptr<FrameSink> sink;
  const std::string path = ::testing::TempDir() + "/" + name;
  EXPECT_TRUE(MakeStreamSink(path, false, &sink).ok());
  d.AddSink(std::move(sink));
  const Status st = RunToEnd(d);
  EXPECT_TRUE(st.ok()) << st.ToString();
  if (stats != nullptr) *stats = d.stats();
  return ReadAll(path);
}

TEST(Daemon, ReplayGivesBitIdenticalFramesEveryRun) {
  DaemonStats stats;
  const std::string first = RenderReplayToPpm(true, "replay_a.ppm", &stats);
  const std::string second = RenderReplayToPpm(true, "replay_b.ppm", nullptr);
  // 0.5 s of script at 10 frames/s: frames at 0, 0.1, ..., 0.5 s.
  EXPECT_EQ(stats.frames, 6);
  // Every drawn frame's time is in the summary's histograms, its parts within the whole.
  EXPECT_GE(stats.renders, 1);
  EXPECT_EQ(stats.render_times.count(), stats.renders);
  EXPECT_EQ(stats.update_times.count(), stats.renders);
  EXPECT_EQ(stats.draw_times.count(), stats.renders);
  EXPECT_LE(stats.update_times.max_us() + stats.draw_times.max_us(), 2 * stats.render_times.max_us() + 1);
  EXPECT_GT(stats.draw_times.max_us(), 0) << "a 96x72 draw takes some microseconds";
  // From the second draw at its camera on, only the shown triangles are drawn
  // (the Cornell blocks' far faces are hidden); the frames above stay identical.
  ASSERT_GE(stats.renders, 2);
  EXPECT_GT(stats.drawn_triangles, 0u);
  EXPECT_LT(stats.drawn_triangles, stats.mesh_triangles);
  const size_t frame_bytes = std::strlen("P6\n96 72\n255\n") + 96 * 72 * 3;
  ASSERT_EQ(first.size(), 6 * frame_bytes);
  EXPECT_TRUE(first == second) << "the same script must give the same bytes";
  EXPECT_NE(first.substr(0, frame_bytes), first.substr(5 * frame_bytes)) << "the script changes the picture";
}

TEST(Daemon, RealTimeReplayShowsTheSameFramesAsScriptTime) {
  DaemonStats stats;
  const std::string script_time = RenderReplayToPpm(true, "replay_script.ppm", nullptr);
  const std::string real_time = RenderReplayToPpm(false, "replay_real.ppm", &stats);
  if (stats.ticks_skipped > 0) GTEST_SKIP() << "machine too busy: " << stats.ticks_skipped << " ticks skipped";
  EXPECT_TRUE(script_time == real_time);
}

// A daemon with a mock source on the Cornell spot; `on_frame` runs after
// each frame and may inject for the next.
struct MockRig {
  explicit MockRig(const std::string& patch_text, int64_t frames, double fps = 100) {
    DaemonConfig c = SmallConfig();
    c.fps = fps;
    c.script_time = true;
    c.max_frames = frames;
    // One file per test: ctest -j runs this binary's tests in parallel processes.
    if (!patch_text.empty()) {
      c.patch_path = WriteTemp(std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                                   "_mock_patch.toml",
                               patch_text);
    }
    const Status st = daemon.Open(c);
    EXPECT_TRUE(st.ok()) << st.ToString();
    auto m = std::make_unique<hal::MockSource>(daemon.patch(), std::vector<uint16_t>(16, 0));
    mock = m.get();
    daemon.AddSource(std::move(m));
  }
  Daemon daemon;
  hal::MockSource* mock = nullptr;
};

TEST(Daemon, MockRegisterWritesReachTheEngineOnTheNextFrame) {
  MockRig rig("", 3);
  std::vector<FixtureState> seen;
  rig.daemon.SetFrameObserver([&](const FrameInfo& f) {
    seen.push_back(rig.daemon.engine().state(0));
    if (f.frame == 0) {
      ASSERT_EQ(rig.mock->SetHoldingRegister(hal::kRegFlags, 1, 1), 0);
      ASSERT_EQ(rig.mock->SetHoldingRegister(hal::kRegDimmer, 65535 / 2, 1), 0);
      ASSERT_EQ(rig.mock->SetHoldingRegister(hal::kRegPan, 32768 + 4096, 1), 0);  // 1/16 of 540 deg
      ASSERT_EQ(rig.mock->SetHoldingRegister(hal::kRegTilt, 32768 - 2048, 1), 0);  // -1/32 of 270 deg
      ASSERT_EQ(rig.mock->SetHoldingRegister(hal::kRegGreen, 51, 1), 0);
    }
    if (f.frame == 1) {
      ASSERT_EQ(rig.mock->SetHoldingRegister(hal::kRegFlags, 0, 2), 0);
    }
  });
  ASSERT_TRUE(RunToEnd(rig.daemon).ok());
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[1].dimmer.raw(), hal::LevelQ15FromRegister16(65535 / 2));
  EXPECT_EQ(seen[1].pan_deg.raw(), 33 * 65536 + 49152);  // 33.75 deg
  EXPECT_EQ(seen[1].tilt_deg.raw(), -(8 * 65536 + 28672));  // -8.4375 deg
  EXPECT_EQ(seen[1].rgb[1].raw(), hal::LevelQ15FromByte(51));
  EXPECT_EQ(rig.mock->frames_reported(), 3u);
  EXPECT_EQ(rig.mock->last_frame(), 3u);
  // Flags off: dark, whatever the dimmer register says.
  EXPECT_EQ(seen[2].dimmer.raw(), 0);
  EXPECT_EQ(rig.mock->holding_register(hal::kRegDimmer), 65535 / 2);
}

// Live input only, real time: the frame loop follows the input (issue 12,
// 44 fps latency). A change that comes right after a render is drawn at
// once, in an early frame, not a period later on a tick; a third change in
// the same period waits for the render budget (one render per period on
// average, a burst of one).
TEST(Daemon, LiveChangesRenderOnArrivalWithinTheRenderBudget) {
  DaemonConfig c = SmallConfig();
  c.fps = 10;  // 100 ms: far longer than a 96x72 render
  c.max_frames = 40;
  c.patch_path = WriteTemp("daemon_live_follow.toml", "[[fixture]]\nname = \"spot\"\nfade_ms = 0\n");
  Daemon d;
  ASSERT_TRUE(d.Open(c).ok());
  auto m = std::make_unique<hal::MockSource>(d.patch(), std::vector<uint16_t>(16, 0));
  hal::MockSource* mock = m.get();
  d.AddSource(std::move(m));
  struct Shown {
    int64_t tick, out_us, render_start_us;
  };
  std::vector<Shown> shown;  // the frames that first show pan 10, 20, 30
  std::atomic<bool> stop{false}, reload{false};
  d.SetFrameObserver([&](const FrameInfo& f) {
    const int32_t want = static_cast<int32_t>(shown.size() + 1) * 10;
    if (f.frame == 2) mock->Inject(ParamChange::Angle(MonotonicUs(), 0, Param::kPan, Q16_16::FromInt(10)));
    if (shown.size() < 3 && d.engine().state(0).pan_deg.raw() == want << 16) {
      shown.push_back({f.tick, f.out_us, f.out_us - f.render_us});
      if (shown.size() < 3) mock->Inject(ParamChange::Angle(MonotonicUs(), 0, Param::kPan, Q16_16::FromInt(want + 10)));
    }
    if (shown.size() == 3) stop = true;
  });
  ASSERT_TRUE(d.Start().ok());
  ASSERT_TRUE(d.Run(stop, reload).ok());
  ASSERT_EQ(shown.size(), 3u) << "a live change never showed";
  EXPECT_EQ(shown[1].tick, -1) << "a change right after a render must be drawn at once, not on the next tick";
  // The third change waits until one period after the render of the first (less the sink, 5 ms slack).
  EXPECT_GE(shown[2].out_us - shown[0].render_start_us, d.period_us() - 5000)
      << "more than two renders in one period";
}

TEST(Daemon, FadesRampLinearlyAndTheSquareCurveShapesTheDimmer) {
  MockRig rig("[[fixture]]\nname = \"spot\"\nfade_ms = 100\ndimmer_curve = \"square\"\n", 14, 100);
  std::vector<FixtureState> seen;
  rig.daemon.SetFrameObserver([&](const FrameInfo& f) {
    seen.push_back(rig.daemon.engine().state(0));
    if (f.frame == 1) {
      // The mock is made from the patch: fixture 0 is the patch's first, "spot".
      rig.mock->Inject(ParamChange::Angle(0, 0, Param::kPan, Q16_16::FromInt(100)));
      // Half: square law gives a quarter.
      rig.mock->Inject(ParamChange::Level(0, 0, Param::kDimmer, Q1_15::FromRaw(16384)));
    }
  });
  ASSERT_TRUE(RunToEnd(rig.daemon).ok());
  ASSERT_EQ(seen.size(), 14u);
  // Targets set at tick 2 (20 ms); 100 ms fade: pan = 100 deg * (t - 20 ms) / 100 ms.
  for (int k = 2; k <= 13; ++k) {
    const int64_t elapsed_ms = (k - 2) * 10 > 100 ? 100 : (k - 2) * 10;
    EXPECT_EQ(seen[static_cast<size_t>(k)].pan_deg.raw(), static_cast<int32_t>((int64_t{100} << 16) * elapsed_ms / 100))
        << "frame " << k;
  }
  EXPECT_EQ(seen[13].dimmer.raw(), 8192);
  // Dimmer ramps in control level, from the bake's default (full), then the curve.
  const int32_t control_mid = 32767 + (16384 - 32767) / 2;
  EXPECT_EQ(seen[7].dimmer.raw(), control::ApplyDimmerCurve(hal::DimmerCurve::kSquare, control_mid));
}

// Zoom over Modbus (issue 12): a patch layout with a zoom register, on the
// Cornell box with a zooming spot (11..60 degrees). The register holds the
// bake's beam angle at start, a write reaches Engine::SetZoom, a write past
// the lens clamps to its range.
TEST(Daemon, AZoomRegisterZoomsTheLuminaire) {
  DaemonConfig c = SmallConfig();
  c.bake_path = test::BakedFixture("cornell_zoom", baker::DirectModeKind::kExact).bake_path;
  c.script_time = true;
  c.max_frames = 3;
  c.patch_path = WriteTemp("daemon_zoom.toml",
                           "[[fixture]]\nname = \"spot\"\nregisters = [\"dimmer\", \"zoom\"]\nfade_ms = 0\n");
  Daemon d;
  const Status st = d.Open(c);
  ASSERT_TRUE(st.ok()) << st.ToString();
  const Q16_16 baked = d.engine().state(0).zoom_deg;
  ASSERT_GT(baked.raw(), 0) << "the spot of cornell_zoom has a zoom";
  auto m = std::make_unique<hal::MockSource>(d.patch(), std::vector<uint16_t>{32767, hal::RegisterFromZoomQ16(baked.raw())});
  hal::MockSource* mock = m.get();
  d.AddSource(std::move(m));
  EXPECT_EQ(hal::RegisterFromZoomQ16(baked.raw()), static_cast<uint16_t>((int64_t{baked.raw()} * 100 + 32768) >> 16));
  std::vector<Q16_16> seen;
  d.SetFrameObserver([&](const FrameInfo& f) {
    seen.push_back(d.engine().state(0).zoom_deg);
    if (f.frame == 0) {
      EXPECT_EQ(mock->SetHoldingRegister(1, 3650, 1), 0);  // 36.5 degrees
    }
    if (f.frame == 1) {
      EXPECT_EQ(mock->SetHoldingRegister(1, 18000, 2), 0);  // 180: past the lens
    }
  });
  ASSERT_TRUE(RunToEnd(d).ok());
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[0], baked);
  EXPECT_EQ(seen[1].raw(), 73 << 15);
  EXPECT_EQ(seen[2].raw(), 60 << 16);  // the lens's widest
}

TEST(Daemon, SighupReloadKeepsTheOldPatchWhenTheNewOneIsBroken) {
  const std::string patch_path = WriteTemp("daemon_reload.toml", "[[fixture]]\nname = \"spot\"\nfade_ms = 0\n");
  DaemonConfig c = SmallConfig();
  c.patch_path = patch_path;
  c.script_time = true;
  c.max_frames = 4;
  Daemon d;
  ASSERT_TRUE(d.Open(c).ok());
  std::atomic<bool> stop{false}, reload{false};
  d.SetFrameObserver([&](const FrameInfo& f) {
    if (f.frame == 0) {
      WriteTemp("daemon_reload.toml", "[[fixture]]\nname = \"spot\"\nfade_ms = 250\n");
      reload.store(true);
    }
    if (f.frame == 1) {
      EXPECT_EQ(d.patch().fixtures[0].fade_ms, 250);
      WriteTemp("daemon_reload.toml", "[[fixture]]\nname = \"nope\"\n");
      reload.store(true);
    }
  });
  ASSERT_TRUE(d.Start().ok());
  ASSERT_TRUE(d.Run(stop, reload).ok());
  EXPECT_EQ(d.stats().reloads, 2);
  EXPECT_EQ(d.stats().reload_failures, 1);
  EXPECT_EQ(d.patch().fixtures[0].fade_ms, 250);
  EXPECT_EQ(d.stats().frames, 4);
}

TEST(Daemon, StartUpErrorsNameWhatFailed) {
  DaemonConfig c = SmallConfig();
  c.patch_path = "/nonexistent/patch.toml";
  Daemon a;
  Status st = a.Open(c);
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("/nonexistent/patch.toml"), std::string::npos);

  c = SmallConfig();
  c.exit_when_replay_done = true;
  Daemon b;
  EXPECT_EQ(b.Open(c).code(), StatusCode::kInvalidArgument);

  MockRig rig("", 1);
  rig.mock->FailStartWith(Status(StatusCode::kNotFound, "console unplugged"));
  st = rig.daemon.Start();
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("input mock: console unplugged"), std::string::npos) << st.message();

  c = SmallConfig();
  c.patch_path = WriteTemp("daemon_busy.toml", "[[gpio_button]]\nchip = \"gpiochip_absent\"\nline = 1\nfixture = \"spot\"\n");
  Daemon g;
  ASSERT_TRUE(g.Open(c).ok());
  st = g.Start();
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("gpiochip_absent"), std::string::npos) << st.message();
}

TEST(Daemon, SinksWritePngPpmRawAndFramebufferFiles) {
  DaemonConfig c = SmallConfig();
  c.script_time = true;
  c.max_frames = 2;
  Daemon d;
  ASSERT_TRUE(d.Open(c).ok());
  const std::string dir = ::testing::TempDir();
  std::unique_ptr<FrameSink> sink;
  EXPECT_EQ(MakePngSequenceSink(dir + "/no_number.png", &sink).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(MakePngSequenceSink(dir + "/two_%d_%d.png", &sink).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(MakePngSequenceSink(dir + "/sink_%03d.png", &sink).ok());
  d.AddSink(std::move(sink));
  ASSERT_TRUE(MakeStreamSink(dir + "/sink.raw", true, &sink).ok());
  d.AddSink(std::move(sink));
  ASSERT_TRUE(MakeFramebufferSink(dir + "/sink.fb", 64, 80, &sink).ok());  // narrower, taller than the frame
  d.AddSink(std::move(sink));
  EXPECT_EQ(MakeFramebufferSink(dir + "/sink2.fb", 0, 0, &sink).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(RunToEnd(d).ok());

  std::vector<uint8_t> png;
  int w = 0, h = 0;
  ASSERT_TRUE(ReadPngRgb8(dir + "/sink_001.png", &png, &w, &h).ok());
  ASSERT_EQ(w, 96);
  ASSERT_EQ(h, 72);
  const std::string raw = ReadAll(dir + "/sink.raw");
  ASSERT_EQ(raw.size(), 2u * 96 * 72 * 3);
  EXPECT_EQ(0, std::memcmp(raw.data() + 96 * 72 * 3, png.data(), png.size()));
  // The framebuffer holds the last frame's top-left 64 x 72 as XRGB8888 (B, G, R, X bytes).
  const std::string fb = ReadAll(dir + "/sink.fb");
  ASSERT_GE(fb.size(), 64u * 72 * 4);
  int mismatches = 0;
  for (int y = 0; y < 72; ++y) {
    for (int x = 0; x < 64; ++x) {
      const uint8_t* p = &png[(static_cast<size_t>(y) * 96 + x) * 3];
      const uint8_t* q = reinterpret_cast<const uint8_t*>(fb.data()) + (static_cast<size_t>(y) * 64 + x) * 4;
      if (q[0] != p[2] || q[1] != p[1] || q[2] != p[0]) ++mismatches;
    }
  }
  EXPECT_EQ(mismatches, 0);
}

}  // namespace
}  // namespace relight::daemon
