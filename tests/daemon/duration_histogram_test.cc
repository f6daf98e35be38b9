// The daemon's duration histogram (runtime/daemon/src/duration_histogram.h):
// quantiles to the bin, the overflow bin, no samples.
#include "duration_histogram.h"

#include <gtest/gtest.h>

namespace relight::daemon {
namespace {

TEST(DurationHistogram, QuantilesAreTheBinsUpperEdges) {
  DurationHistogram h;
  EXPECT_EQ(h.QuantileUs(500), 0) << "no samples";
  for (int64_t k = 1; k <= 1000; ++k) h.Add(k * 100 - 50);  // 0.05, 0.15, ..., 99.95 ms
  EXPECT_EQ(h.count(), 1000);
  EXPECT_EQ(h.max_us(), 99950);
  EXPECT_EQ(h.QuantileUs(500), 50000);   // the 500th sample, 49.95 ms, lies in [49.9, 50.0) ms
  EXPECT_EQ(h.QuantileUs(990), 99000);
  EXPECT_EQ(h.QuantileUs(1000), 100000);
  EXPECT_EQ(h.QuantileUs(0), 100) << "the smallest sample's bin";
}

TEST(DurationHistogram, PastTheLastBinTheLargestSampleIsReported) {
  DurationHistogram h;
  for (int k = 0; k < 98; ++k) h.Add(1000);
  h.Add(300000);  // 300 ms, past the 250 ms of bins
  h.Add(-5);      // a clock step back counts as 0
  EXPECT_EQ(h.QuantileUs(500), 1100);
  EXPECT_EQ(h.QuantileUs(995), 300000);
  EXPECT_EQ(h.QuantileUs(10), 100);
}

}  // namespace
}  // namespace relight::daemon
