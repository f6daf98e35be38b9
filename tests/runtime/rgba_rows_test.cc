// The RGBA -> RGB row copy (rgba_rows.h): the shuffle path against the byte
// loop on every row length that leaves a loop tail, and nothing written past
// the row's end (the 16-byte stores overrun within the row only).
#include "rgba_rows.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

namespace relight::render {
namespace {

TEST(RgbaRows, ShuffleMatchesTheByteLoopAndStaysInsideTheRow) {
  std::mt19937 rng(7);
  constexpr uint8_t kGuard = 0xA5;
  constexpr size_t kGuardBytes = 32;
  std::vector<size_t> lengths;
  for (size_t n = 0; n <= 70; ++n) lengths.push_back(n);
  lengths.push_back(1280);
  lengths.push_back(1283);
  for (const size_t n : lengths) {
    std::vector<uint8_t> src(4 * n);
    for (uint8_t& b : src) b = static_cast<uint8_t>(rng());
    std::vector<uint8_t> fast(3 * n + kGuardBytes, kGuard), ref(3 * n + kGuardBytes, kGuard);
    RgbaRowToRgb(src.data(), n, fast.data());
    RgbaRowToRgbScalar(src.data(), n, ref.data());
    ASSERT_EQ(fast, ref) << n << " pixels";
    for (size_t i = 0; i < n; ++i) {
      ASSERT_EQ(ref[3 * i + 0], src[4 * i + 0]);
      ASSERT_EQ(ref[3 * i + 1], src[4 * i + 1]);
      ASSERT_EQ(ref[3 * i + 2], src[4 * i + 2]);
    }
    for (size_t i = 3 * n; i < fast.size(); ++i)
      ASSERT_EQ(fast[i], kGuard) << n << " pixels, byte " << i;
  }
}

}  // namespace
}  // namespace relight::render
