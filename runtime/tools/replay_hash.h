// Frame hashes for bit-exactness checks: FNV-1a 64 over values in a fixed
// byte order (little-endian), so a hash means the same on every target.
#pragma once

#include <cstdint>

namespace relight::cli {

inline constexpr uint64_t kFnv1a64Offset = 0xcbf29ce484222325ull;

// Continues `hash` over `count` int32 values, each as 4 little-endian bytes.
uint64_t HashInt32Le(const int32_t* values, uint64_t count, uint64_t hash = kFnv1a64Offset);
// Continues `hash` over `count` bytes.
uint64_t HashBytes(const uint8_t* bytes, uint64_t count, uint64_t hash = kFnv1a64Offset);

}  // namespace relight::cli
