// A fixed-capacity FIFO of parameter changes for sources whose changes are
// produced ahead of Poll() (GPIO edges, mock injections). When full, the
// oldest change is dropped and counted: a stuck consumer cannot grow memory.
//
// Thread safety: none; the owner serialises access.
#pragma once

#include <cstddef>
#include <vector>

#include "relight/base/param.h"

namespace relight::hal {

class ChangeRing {
 public:
  explicit ChangeRing(size_t capacity) : items_(capacity) {}
  void Push(const ParamChange& change) {
    if (count_ == items_.size()) {
      head_ = (head_ + 1) % items_.size();
      --count_;
      ++dropped_;
    }
    items_[(head_ + count_) % items_.size()] = change;
    ++count_;
  }
  // Moves changes due at or before now_us, oldest first, up to capacity.
  size_t PopDue(int64_t now_us, ParamChange* out, size_t capacity) {
    size_t n = 0;
    while (n < capacity && count_ > 0 && items_[head_].time_us <= now_us) {
      out[n++] = items_[head_];
      head_ = (head_ + 1) % items_.size();
      --count_;
    }
    return n;
  }
  size_t size() const { return count_; }
  size_t dropped() const { return dropped_; }

 private:
  std::vector<ParamChange> items_;
  size_t head_ = 0, count_ = 0, dropped_ = 0;
};

}  // namespace relight::hal
