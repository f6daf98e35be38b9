// relightd hands llvmpipe's compiler (libLLVM) back to the kernel after the
// second drawn frame (startup_memory.h, render/compiler_pages.h), unless its
// config keeps it. Its own binary, run alone (RUN_SERIAL): a page another
// process maps too is shared, and the kernel leaves shared pages resident.
#include <gtest/gtest.h>

#include "common/smaps.h"
#include "daemon_test_support.h"

namespace relight::daemon {
namespace {

const char* kScript =
    "0.0  spot.dimmer=0.8  spot.pan=0  spot.tilt=10\n"
    "0.25 spot.tilt=35  spot.colour=1,0.5,0.2\n"
    "0.5  spot.pan=90   spot.dimmer=0.3\n";

// libLLVM's pages after a short replay, with or without the release.
test::SmapsKb LlvmAfterReplay(bool release) {
  DaemonConfig c = testing::SmallConfig();
  c.replay_path = testing::WriteTemp(std::string("pages_") + (release ? "r" : "k") + ".replay", kScript);
  c.script_time = true;
  c.exit_when_replay_done = true;
  c.release_startup_memory = release;
  Daemon d;
  const Status open = d.Open(c);
  EXPECT_TRUE(open.ok()) << open.ToString();
  const Status st = testing::RunToEnd(d);
  EXPECT_TRUE(st.ok()) << st.ToString();
  EXPECT_GE(d.stats().renders, 2);
  return test::SmapsOfPath("libLLVM");
}

TEST(StartupMemory, TheShaderCompilerLeavesTheResidentSetAfterTwoFrames) {
  const test::SmapsKb kept = LlvmAfterReplay(false);
  if (!kept.any) GTEST_SKIP() << "no libLLVM mapped: OSMesa here does not use llvmpipe";
  EXPECT_GT(kept.rss, 8192) << "llvmpipe touched less of libLLVM than expected: the test shows nothing";
  if (kept.private_clean < 8192) {
    GTEST_SKIP() << "another process maps libLLVM too (" << kept.shared_clean
                 << " kB shared): the kernel keeps shared pages, so the release cannot be seen here";
  }
  const test::SmapsKb released = LlvmAfterReplay(true);
  EXPECT_LT(released.private_clean, 2048) << "libLLVM pages still resident after the release (kept: "
                                          << kept.private_clean << " kB)";
}

}  // namespace
}  // namespace relight::daemon
