// The clock live inputs stamp their changes with: CLOCK_MONOTONIC in
// microseconds. The daemon reads the same clock, so "arrival -> frame out"
// latencies are differences of two readings of it.
#pragma once

#include <cstdint>

namespace relight {

int64_t MonotonicUs();

}  // namespace relight
