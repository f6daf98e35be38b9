// The shown-triangle list from an ID pass (visible_triangles.h): draw order
// kept, each triangle once however many pixels it wins, background and
// out-of-range codes ignored.
#include "visible_triangles.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace relight::render {
namespace {

void Put(std::vector<uint8_t>* rgba, size_t pixel, uint32_t code) {
  (*rgba)[4 * pixel + 0] = static_cast<uint8_t>(code & 0xFF);
  (*rgba)[4 * pixel + 1] = static_cast<uint8_t>((code >> 8) & 0xFF);
  (*rgba)[4 * pixel + 2] = static_cast<uint8_t>((code >> 16) & 0xFF);
  (*rgba)[4 * pixel + 3] = 0xFF;
}

TEST(VisibleTriangles, ListsEachShownTriangleOnceInDrawOrder) {
  const uint32_t triangles[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 70000, 70001, 70002};
  constexpr uint32_t kTriangles = 5;
  std::vector<uint8_t> rgba(4 * 8, 0);
  Put(&rgba, 0, 4);         // triangle 3
  Put(&rgba, 1, 2);         // triangle 1
  Put(&rgba, 2, 4);         // triangle 3 again
  Put(&rgba, 3, 5);         // triangle 4: code above 2^16 in its indices, still listed
  Put(&rgba, 4, 6);         // beyond the triangle count: ignored
  Put(&rgba, 5, 0xFFFFFF);  // ignored
  std::vector<uint8_t> seen(kTriangles, 0xCC);
  std::vector<uint32_t> out(3 * kTriangles, 0xDEADBEEF);
  const uint32_t shown =
      CompactVisibleTriangles(rgba.data(), 8, triangles, kTriangles, seen.data(), out.data());
  ASSERT_EQ(shown, 3u);
  const std::vector<uint32_t> expect = {3, 4, 5, 9, 10, 11, 70000, 70001, 70002};
  EXPECT_EQ(std::vector<uint32_t>(out.begin(), out.begin() + 9), expect);
  EXPECT_EQ(out[9], 0xDEADBEEFu);  // nothing past the shown ones
  EXPECT_EQ(TriangleCode(rgba.data() + 4 * 3), 5u);

  std::vector<uint8_t> background(4 * 8, 0);
  EXPECT_EQ(
      CompactVisibleTriangles(background.data(), 8, triangles, kTriangles, seen.data(), out.data()),
      0u);
}

}  // namespace
}  // namespace relight::render
