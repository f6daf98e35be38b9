// Frame comparison for golden-image tests: two RGB8 images match when at most
// a given fraction of pixels differ by more than a per-channel tolerance. On
// a mismatch the actual image and a diff image are written as PNGs so a
// failing CI run leaves something to look at.
#pragma once

#include <cstdint>
#include <string>

#include <gtest/gtest.h>

namespace relight {
namespace test_image {

// An RGB8 image, top row first, width * height * 3 bytes; not owned.
struct Rgb8View {
  const uint8_t* rgb = nullptr;
  int width = 0;
  int height = 0;
};

struct Tolerance {
  int channel_levels = 2;          // |expected - actual| allowed per channel, 0..255
  double max_bad_fraction = 0.0;   // fraction of pixels allowed beyond channel_levels
};

struct DiffStats {
  int max_channel_diff = 0;   // worst |expected - actual| over all channels
  int64_t bad_pixels = 0;     // pixels with any channel beyond the tolerance
  double bad_fraction = 0.0;  // bad_pixels / (width * height)
};

// Same-size images only (the caller checks sizes; see ImagesMatch).
DiffStats DiffRgb8(const Rgb8View& expected, const Rgb8View& actual, int channel_levels);

// Diff image: red where a pixel is beyond the tolerance, green (amplified 32x)
// where it differs within it, the actual image at quarter brightness elsewhere.
void MakeDiffImage(const Rgb8View& expected, const Rgb8View& actual, int channel_levels, uint8_t* out_rgb);

// Success, or a failure naming the numbers and the two PNGs written as
// <artifact_stem>_actual.png and <artifact_stem>_diff.png.
::testing::AssertionResult ImagesMatch(const Rgb8View& expected, const Rgb8View& actual,
                                       const Tolerance& tolerance, const std::string& artifact_stem);

// Compares against a golden PNG. With RELIGHT_UPDATE_GOLDEN=1 in the
// environment the golden file is (re)written from `actual` instead.
::testing::AssertionResult MatchesGoldenPng(const std::string& golden_path, const Rgb8View& actual,
                                            const Tolerance& tolerance, const std::string& artifact_stem);

}  // namespace test_image
}  // namespace relight
