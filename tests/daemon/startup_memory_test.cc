// relightd has llvmpipe compile its shaders on a stand-in triangle, then
// hands the compiler (libLLVM) back to the kernel before the bake is read
// (startup_memory.h, render/compiler_pages.h), unless its config keeps it;
// the frames then compile nothing, so the compiler stays out. Its own binary, run alone (RUN_SERIAL): a page another
// process maps too is shared, and the kernel leaves shared pages resident.
#include <gtest/gtest.h>

#include <algorithm>

#include "common/smaps.h"
#include "daemon_test_support.h"

namespace relight::daemon {
namespace {

const char* kScript =
    "0.0  spot.dimmer=0.8  spot.pan=0  spot.tilt=10\n"
    "0.25 spot.tilt=35  spot.colour=1,0.5,0.2\n"
    "0.5  spot.pan=90   spot.dimmer=0.3\n";

// libLLVM's pages after a short replay, with or without the release;
// `most_in_frames`: the most Private_Clean seen after Open and after each of
// the first three frames.
test::SmapsKb LlvmAfterReplay(bool release, long* most_in_frames) {
  DaemonConfig c = testing::SmallConfig();
  c.replay_path = testing::WriteTemp(std::string("pages_") + (release ? "r" : "k") + ".replay", kScript);
  c.script_time = true;
  c.exit_when_replay_done = true;
  c.release_startup_memory = release;
  Daemon d;
  const Status open = d.Open(c);
  EXPECT_TRUE(open.ok()) << open.ToString();
  *most_in_frames = test::SmapsOfPath("libLLVM").private_clean;
  d.SetFrameObserver([most_in_frames](const FrameInfo& f) {
    if (f.frame < 3) *most_in_frames = std::max(*most_in_frames, test::SmapsOfPath("libLLVM").private_clean);
  });
  const Status st = testing::RunToEnd(d);
  EXPECT_TRUE(st.ok()) << st.ToString();
  EXPECT_GE(d.stats().renders, 2);
  return test::SmapsOfPath("libLLVM");
}

TEST(StartupMemory, TheShaderCompilerLeavesBeforeTheBakeAndDoesNotComeBack) {
  long kept_most = 0, released_most = 0;
  const test::SmapsKb kept = LlvmAfterReplay(false, &kept_most);
  if (!kept.any) GTEST_SKIP() << "no libLLVM mapped: OSMesa here does not use llvmpipe";
  EXPECT_GT(kept.rss, 8192) << "llvmpipe touched less of libLLVM than expected: the test shows nothing";
  if (kept.private_clean < 8192) {
    GTEST_SKIP() << "another process maps libLLVM too (" << kept.shared_clean
                 << " kB shared): the kernel keeps shared pages, so the release cannot be seen here";
  }
  const test::SmapsKb released = LlvmAfterReplay(true, &released_most);
  EXPECT_LT(released_most, 2048) << "libLLVM pages resident after Open or in the first frames: a shader the "
                                    "warm-up missed? (kept: "
                                 << kept.private_clean << " kB)";
  EXPECT_LT(released.private_clean, 2048) << "libLLVM pages resident at the end";
}

}  // namespace
}  // namespace relight::daemon
