// Issue 17: relight-render --replay plans its frames in 64-bit arithmetic
// and refuses more than kMaxReplayFrames (or an --fps out of range) before
// rendering anything, instead of hanging or overflowing an int.
#include <gtest/gtest.h>

#include <string>

#include "relight/hal/replay_source.h"
#include "replay_plan.h"

namespace relight::cli {
namespace {

TEST(ReplayPlan, FramesFromStartToTheLastChangeInclusive) {
  ReplayPlan plan;
  std::string error;
  ASSERT_TRUE(PlanReplayFrames(2000000, 5, &plan, &error)) << error;
  EXPECT_EQ(plan.frame_us, 200000);
  EXPECT_EQ(plan.frames, 11);
  ASSERT_TRUE(PlanReplayFrames(0, 240, &plan, &error)) << error;
  EXPECT_EQ(plan.frames, 1);
  // Exactly the limit still plans: 99999 frame steps of 1/30 s.
  ASSERT_TRUE(PlanReplayFrames(int64_t{99999} * 33333, 30, &plan, &error)) << error;
  EXPECT_EQ(plan.frames, kMaxReplayFrames);
}

TEST(ReplayPlan, TooManyFramesOrABadFpsIsAClearError) {
  ReplayPlan plan;
  std::string error;
  // The script time the parser allows (1e7 s) at the highest fps: 2.4e9
  // frames, more than an int holds.
  EXPECT_FALSE(PlanReplayFrames(int64_t{10000000} * 1000000, 240, &plan, &error));
  EXPECT_NE(error.find("the script runs 10000000 s: at 240 fps that is 2399808016 frames, more "
                       "than the limit of 100000"),
            std::string::npos)
      << error;
  EXPECT_FALSE(PlanReplayFrames(1000000, 1000, &plan, &error));
  EXPECT_NE(error.find("--fps must be in 0.1..240, got 1000"), std::string::npos) << error;
  EXPECT_FALSE(PlanReplayFrames(1000000, 0, &plan, &error));
  EXPECT_FALSE(PlanReplayFrames(1000000, -5, &plan, &error));
}

TEST(ReplayPlan, TheLongScriptFixtureIsRefusedBeforeAnyFrame) {
  hal::ReplaySource source(std::string(RELIGHT_SOURCE_DIR) +
                           "/fixtures/malformed/replay_long_time.replay",
                           {"ceiling_spot"});
  ASSERT_TRUE(source.Start().ok());
  EXPECT_EQ(source.duration_us(), int64_t{10000000} * 1000000);
  ReplayPlan plan;
  std::string error;
  EXPECT_FALSE(PlanReplayFrames(source.duration_us(), 5, &plan, &error));
  EXPECT_NE(error.find("that is 50000001 frames, more than the limit of 100000"), std::string::npos)
      << error;
}

}  // namespace
}  // namespace relight::cli
