// Tone map (relight/tone_map.h) against its float64 definition:
// y = x (1 + x/16) / (1 + x), x = L / white, then sRGB to 8 bits.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include "relight/engine/tone_map.h"

namespace relight {
namespace {

double SrgbEncode(double y) {
  return y <= 0.0031308 ? 12.92 * y : 1.055 * std::pow(y, 1.0 / 2.4) - 0.055;
}
double Shoulder(double x) { return x * (1.0 + x / 16.0) / (1.0 + x); }
// The code as a real number before rounding.
double FloatCode(double luminance_q12, double white_q12) {
  const double y = std::min(1.0, Shoulder(luminance_q12 / white_q12));
  return 255.0 * SrgbEncode(y);
}

uint8_t MapOne(const ToneMap& map, int32_t l) {
  const int32_t rgb[3] = {l, l, l};
  uint8_t out[3];
  ToneMapRgb8(map, LuminanceView(rgb, 1), out);
  EXPECT_EQ(out[0], out[1]);
  EXPECT_EQ(out[0], out[2]);
  return out[0];
}

class ToneMapTest : public ::testing::TestWithParam<int32_t> {};

TEST_P(ToneMapTest, CurveIsMonotonicSaturatesAndMatchesFloat) {
  const int32_t white = GetParam();
  auto map = std::make_unique<ToneMap>();
  BuildToneMap(white, map.get());
  EXPECT_EQ(map->white_q12, white);
  // Monotonic, 0 -> 0, the last entry (>= 4x white) is 255.
  for (int i = 1; i < kToneMapEntries; ++i) ASSERT_GE(map->table[i], map->table[i - 1]) << i;
  EXPECT_GE(int64_t{kToneMapEntries - 1} << map->shift, 4 * int64_t{white});
  EXPECT_EQ(MapOne(*map, 0), 0);
  EXPECT_EQ(MapOne(*map, -5000), 0);
  if (4 * int64_t{white} <= std::numeric_limits<int32_t>::max()) {  // 4x white is representable
    EXPECT_EQ(MapOne(*map, 4 * white), 255);
    EXPECT_EQ(MapOne(*map, std::numeric_limits<int32_t>::max()), 255);
  }
  // White: y = 17/32 -> sRGB 0.757 -> code 193.
  EXPECT_EQ(std::lround(FloatCode(white, white)), 193);
  EXPECT_NEAR(MapOne(*map, white), 193, 1);
  // Every entry is the rounded float code at its lower edge, except where
  // the float code lies within 1e-3 of a rounding tie.
  int exact = 0, ties = 0;
  for (int i = 0; i < kToneMapEntries; ++i) {
    const double code = FloatCode(static_cast<double>(int64_t{i} << map->shift), white);
    const double frac = code - std::floor(code);
    if (std::fabs(frac - 0.5) < 1e-3) {
      ++ties;
      EXPECT_NEAR(map->table[i], code, 0.501) << i;
    } else {
      EXPECT_EQ(map->table[i], std::lround(code)) << i;
      ++exact;
    }
  }
  std::printf("  white %d (Q12): shift %d, %d entries equal to float, %d near ties\n", white,
              map->shift, exact, ties);
}

INSTANTIATE_TEST_SUITE_P(Whites, ToneMapTest,
                         ::testing::Values(1, 4096, 100 << 12, 12345 << 12,
                                           std::numeric_limits<int32_t>::max()));

TEST(ToneMap, KnownSrgbPoints) {
  auto map = std::make_unique<ToneMap>();
  const int32_t white = 1 << 20;  // with x in [0, 4): y = 1 needs x = 4
  BuildToneMap(white, map.get());
  // Points where y is known in closed form: x = 4 -> y = 1 -> 255;
  // x = 1 -> y = 17/32 -> 193; x = 0.5 -> y = 0.5 (1 + 1/32) / 1.5 = 0.34375 -> 158.38 -> 158.
  EXPECT_EQ(MapOne(*map, 4 * white), 255);
  EXPECT_EQ(MapOne(*map, white / 2), std::lround(FloatCode(white / 2, white)));
  EXPECT_EQ(std::lround(FloatCode(white / 2, white)), 158);
  // Dark end: the first non-zero code comes at the sRGB threshold 0.5/255/12.92.
  const double first = 0.5 / 255.0 / 12.92;
  int first_nonzero = -1;
  for (int i = 0; i < kToneMapEntries && first_nonzero < 0; ++i) {
    if (map->table[i] != 0) first_nonzero = i;
  }
  ASSERT_GT(first_nonzero, 0);
  const double x = static_cast<double>(int64_t{first_nonzero} << map->shift) / white;
  EXPECT_GE(Shoulder(x), first);
  const double x_prev = static_cast<double>(int64_t{first_nonzero - 1} << map->shift) / white;
  EXPECT_LT(Shoulder(x_prev), first);
}

TEST(ToneMap, DarkEndDoesNotBand) {
  // Below 1/4 of white every luminance maps within one code of the float
  // curve, and one LSB steps of the fine table never jump more than 1 code.
  auto map = std::make_unique<ToneMap>();
  const int32_t white = 200 << 12;  // 200 cd/m^2
  BuildToneMap(white, map.get());
  int worst = 0;
  for (int32_t l = 0; l < white / 4; l += 7) {
    const int diff = std::abs(MapOne(*map, l) - static_cast<int>(std::lround(FloatCode(l, white))));
    worst = std::max(worst, diff);
  }
  EXPECT_LE(worst, 1);
  for (int i = 1; i < kToneMapEntries; ++i) EXPECT_LE(map->fine[i] - map->fine[i - 1], 1) << i;
}

}  // namespace
}  // namespace relight
