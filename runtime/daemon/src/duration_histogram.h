// Percentiles of the daemon's per-frame durations (render, engine update,
// tone map + draw) for its summary line, without storing the samples: counts
// in 0.1 ms bins up to 250 ms, one bin past that. A frame's time costs one
// increment and no allocation, however long relightd runs.
#pragma once

#include <cstdint>

namespace relight::daemon {

class DurationHistogram {
 public:
  static constexpr int64_t kBinUs = 100;
  static constexpr int kBins = 2500;  // [0, 250 ms) in 0.1 ms steps, then one overflow bin

  void Add(int64_t us) {
    const int64_t bin = us < 0 ? 0 : us / kBinUs;
    ++counts_[bin < kBins ? bin : kBins];
    ++count_;
    if (us > max_us_) max_us_ = us;
  }
  int64_t count() const { return count_; }
  int64_t max_us() const { return max_us_; }
  // The upper edge of the bin holding the quantile `permille` / 1000 (500:
  // the median, 990: p99), in microseconds: at most 0.1 ms above the true
  // value; the largest sample when it falls in the overflow bin; 0 with no
  // samples.
  int64_t QuantileUs(int permille) const {
    if (count_ == 0) return 0;
    int64_t rank = (static_cast<int64_t>(permille) * count_ + 999) / 1000;  // the ceil-th sample, from 1
    if (rank < 1) rank = 1;
    int64_t seen = 0;
    for (int b = 0; b < kBins; ++b) {
      seen += counts_[b];
      if (seen >= rank) return (b + 1) * kBinUs;
    }
    return max_us_;
  }

 private:
  uint32_t counts_[kBins + 1] = {};
  int64_t count_ = 0;
  int64_t max_us_ = 0;
};

}  // namespace relight::daemon
