#include "register_input.h"

#include <algorithm>

namespace relight::hal {

RegisterInput::RegisterInput(const RegisterMap& map, std::vector<uint16_t> initial)
    : map_(map),
      latest_(std::move(initial)),
      arrival_us_(static_cast<size_t>(map.fixture_count()), 0),
      dirty_(static_cast<size_t>(map.fixture_count()), 0),
      pending_(static_cast<size_t>(map.fixture_count()) * kParamCount) {
  latest_.resize(static_cast<size_t>(map.holding_count()), 0);
  emitted_ = latest_;
}

void RegisterInput::Write(int addr, int count, const uint16_t* values, int64_t arrival_us) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (int i = 0; i < count; ++i) {
    const int a = addr + i;
    if (a < 0 || a >= map_.holding_count()) continue;
    latest_[static_cast<size_t>(a)] = values[i];
    int offset = 0;
    const int fixture = map_.FixtureAt(a, &offset);
    if (fixture < 0) continue;
    dirty_[static_cast<size_t>(fixture)] = 1;
    arrival_us_[static_cast<size_t>(fixture)] = arrival_us;
  }
}

size_t RegisterInput::Collect(ParamChange* out, size_t capacity) {
  if (pending_next_ >= pending_count_) {
    pending_count_ = pending_next_ = 0;
    std::lock_guard<std::mutex> lock(mutex_);
    for (int f = 0; f < map_.fixture_count(); ++f) {
      if (!dirty_[static_cast<size_t>(f)]) continue;
      dirty_[static_cast<size_t>(f)] = 0;
      const size_t base = static_cast<size_t>(map_.fixture(f).modbus_base);
      uint16_t* before = &emitted_[base];
      const uint16_t* after = &latest_[base];
      pending_count_ += map_.DecodeChanges(f, before, after, arrival_us_[static_cast<size_t>(f)],
                                           &pending_[pending_count_]);
      std::copy(after, after + map_.fixture(f).layout.size(), before);
    }
  }
  size_t n = 0;
  while (n < capacity && pending_next_ < pending_count_) out[n++] = pending_[pending_next_++];
  return n;
}

std::vector<uint16_t> RegisterInput::Snapshot() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return latest_;
}

}  // namespace relight::hal
