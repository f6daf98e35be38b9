// Holding registers shared between a backend's thread (a Modbus server or
// poller writing what arrived) and the daemon's thread (polling changes).
// Coalesces: the daemon sees the newest value of every register, never a
// stale one, and the storage is fixed at construction, so a burst of writes
// can neither overflow a queue nor lose the last value written.
//
// Thread safety: Write() and Snapshot() from any thread; Collect() from the
// one polling thread.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

#include "relight/base/param.h"
#include "relight/hal/register_map.h"

namespace relight::hal {

class RegisterInput {
 public:
  // `initial`: holding_count() values, the state the registers start in
  // (no change is reported for them).
  RegisterInput(const RegisterMap& map, std::vector<uint16_t> initial);

  const RegisterMap& map() const { return map_; }
  // Registers [addr, addr + count) now hold `values`, which arrived at
  // arrival_us. The caller has checked them (RegisterMap::CheckWrite).
  void Write(int addr, int count, const uint16_t* values, int64_t arrival_us);
  // Parameter changes since the last call, each stamped with the newest
  // arrival of its fixture's registers. Changes that do not fit in
  // `capacity` stay for the next call.
  size_t Collect(ParamChange* out, size_t capacity);
  // Copy of the registers as written so far.
  std::vector<uint16_t> Snapshot() const;

 private:
  const RegisterMap map_;
  mutable std::mutex mutex_;
  std::vector<uint16_t> latest_;         // guarded by mutex_
  std::vector<int64_t> arrival_us_;      // per fixture, guarded by mutex_
  std::vector<uint8_t> dirty_;           // per fixture, guarded by mutex_
  // Collect()'s own state.
  std::vector<uint16_t> emitted_;        // register image already turned into changes
  std::vector<ParamChange> pending_;     // fixed capacity: kParamCount per fixture
  size_t pending_count_ = 0, pending_next_ = 0;
};

}  // namespace relight::hal
