#include "replay_hash.h"

namespace relight::cli {
namespace {

constexpr uint64_t kFnv1a64Prime = 0x100000001b3ull;

inline uint64_t Step(uint64_t hash, uint8_t byte) { return (hash ^ byte) * kFnv1a64Prime; }

}  // namespace

uint64_t HashInt32Le(const int32_t* values, uint64_t count, uint64_t hash) {
  for (uint64_t i = 0; i < count; ++i) {
    const uint32_t v = static_cast<uint32_t>(values[i]);
    for (int b = 0; b < 4; ++b) hash = Step(hash, static_cast<uint8_t>(v >> (8 * b)));
  }
  return hash;
}

uint64_t HashBytes(const uint8_t* bytes, uint64_t count, uint64_t hash) {
  for (uint64_t i = 0; i < count; ++i) hash = Step(hash, bytes[i]);
  return hash;
}

}  // namespace relight::cli
