#include "common/image_compare.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "relight/render/osmesa_frame.h"

namespace relight {
namespace test_image {
namespace {

void SetRgb(uint8_t* o, int r, int g, int b) {
  o[0] = static_cast<uint8_t>(r);
  o[1] = static_cast<uint8_t>(g);
  o[2] = static_cast<uint8_t>(b);
}

size_t PixelCount(const Rgb8View& v) { return static_cast<size_t>(v.width) * static_cast<size_t>(v.height); }

int PixelDiff(const uint8_t* a, const uint8_t* b) {
  int worst = 0;
  for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(int{a[c]} - int{b[c]}));
  return worst;
}

}  // namespace

DiffStats DiffRgb8(const Rgb8View& expected, const Rgb8View& actual, int channel_levels) {
  DiffStats stats;
  const size_t n = PixelCount(actual);
  for (size_t i = 0; i < n; ++i) {
    const int d = PixelDiff(expected.rgb + i * 3, actual.rgb + i * 3);
    stats.max_channel_diff = std::max(stats.max_channel_diff, d);
    if (d > channel_levels) ++stats.bad_pixels;
  }
  stats.bad_fraction = n > 0 ? static_cast<double>(stats.bad_pixels) / static_cast<double>(n) : 0.0;
  return stats;
}

void MakeDiffImage(const Rgb8View& expected, const Rgb8View& actual, int channel_levels, uint8_t* out_rgb) {
  const size_t n = PixelCount(actual);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* a = actual.rgb + i * 3;
    uint8_t* o = out_rgb + i * 3;
    const int d = PixelDiff(expected.rgb + i * 3, a);
    if (d > channel_levels) {
      SetRgb(o, 255, 0, 0);
    } else if (d > 0) {
      SetRgb(o, 0, std::min(255, 64 + 32 * d), 0);
    } else {
      const int grey = (a[0] + a[1] + a[2]) / 12;  // quarter of the mean
      SetRgb(o, grey, grey, grey);
    }
  }
}

::testing::AssertionResult ImagesMatch(const Rgb8View& expected, const Rgb8View& actual,
                                       const Tolerance& tolerance, const std::string& artifact_stem) {
  const std::string actual_path = artifact_stem + "_actual.png";
  const std::string diff_path = artifact_stem + "_diff.png";
  if (expected.width != actual.width || expected.height != actual.height) {
    const Status st = WritePngRgb8(actual_path, actual.rgb, actual.width, actual.height);
    return ::testing::AssertionFailure()
           << "image size " << actual.width << "x" << actual.height << " != expected " << expected.width << "x"
           << expected.height << "; actual: " << (st.ok() ? actual_path : st.ToString());
  }
  const DiffStats stats = DiffRgb8(expected, actual, tolerance.channel_levels);
  if (stats.bad_fraction <= tolerance.max_bad_fraction) return ::testing::AssertionSuccess();

  std::vector<uint8_t> diff(PixelCount(actual) * 3);
  MakeDiffImage(expected, actual, tolerance.channel_levels, diff.data());
  const Status st_actual = WritePngRgb8(actual_path, actual.rgb, actual.width, actual.height);
  const Status st_diff = WritePngRgb8(diff_path, diff.data(), actual.width, actual.height);
  return ::testing::AssertionFailure()
         << stats.bad_pixels << " pixels (" << stats.bad_fraction * 100 << "%) differ by more than "
         << tolerance.channel_levels << " levels (max " << tolerance.max_bad_fraction * 100
         << "% allowed; worst " << stats.max_channel_diff << " levels); actual: "
         << (st_actual.ok() ? actual_path : st_actual.ToString())
         << ", diff: " << (st_diff.ok() ? diff_path : st_diff.ToString());
}

::testing::AssertionResult MatchesGoldenPng(const std::string& golden_path, const Rgb8View& actual,
                                            const Tolerance& tolerance, const std::string& artifact_stem) {
  const char* update = std::getenv("RELIGHT_UPDATE_GOLDEN");
  if (update != nullptr && std::strcmp(update, "1") == 0) {
    const Status st = WritePngRgb8(golden_path, actual.rgb, actual.width, actual.height);
    if (!st.ok()) return ::testing::AssertionFailure() << "updating golden: " << st.ToString();
    return ::testing::AssertionSuccess() << "golden updated: " << golden_path;
  }
  std::vector<uint8_t> golden;
  int width = 0, height = 0;
  const Status st = ReadPngRgb8(golden_path, &golden, &width, &height);
  if (!st.ok()) {
    const std::string actual_path = artifact_stem + "_actual.png";
    const Status st_actual = WritePngRgb8(actual_path, actual.rgb, actual.width, actual.height);
    return ::testing::AssertionFailure() << "golden unreadable (" << st.ToString() << "); actual: "
                                         << (st_actual.ok() ? actual_path : st_actual.ToString())
                                         << "; rerun with RELIGHT_UPDATE_GOLDEN=1 to create it";
  }
  return ImagesMatch(Rgb8View{golden.data(), width, height}, actual, tolerance, artifact_stem);
}

}  // namespace test_image
}  // namespace relight
