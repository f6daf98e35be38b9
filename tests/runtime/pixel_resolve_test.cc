// The still-camera resolve's integer side (pixel_resolve.h): the rounding
// division, the slot numbering, and a frame from a hand-made table: rows
// flipped from GL's order, background, weights applied to the right vertices.
// Its geometry against llvmpipe and the float64 reference is in
// osmesa_frame_test.cc.
#include "pixel_resolve.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace relight::render {
namespace {

void Put(std::vector<uint8_t>* table, size_t pixel, uint32_t entry) {
  std::memcpy(table->data() + 4 * pixel, &entry, 4);
}

TEST(PixelResolve, DivideBy255RoundsEveryWeightedSumExactly) {
  for (uint32_t s = 0; s <= 255u * 255u; ++s) {
    const uint32_t want = (2 * s + 255) / 510;  // round(s / 255); no ties, 255 is odd
    ASSERT_EQ(DivideBy255Rounded(s), want) << s;
  }
}

// The spread colours weighed all three channels at once give every channel
// what the scalar formula gives, over random colours and weights.
TEST(PixelResolve, SpreadChannelsWeighLikeOneChannelAtATime) {
  uint32_t state = 12345;
  const auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return state >> 8;
  };
  const uint32_t shown[3] = {0, 1, 2};
  for (int trial = 0; trial < 20000; ++trial) {
    uint8_t rgb[9];
    for (uint8_t& c : rgb) c = static_cast<uint8_t>(next());
    if (trial % 7 == 0) std::memset(rgb, 255, sizeof(rgb));  // the largest sums
    const uint32_t w1 = next() % 256, w2 = next() % (256 - w1), w0 = 255 - w1 - w2;
    uint64_t colours[3];
    GatherSlotColours(shown, 1, rgb, colours);
    std::vector<uint8_t> table(4);
    Put(&table, 0, 0u | w1 << 16 | w2 << 24);
    uint8_t out[3];
    ResolvePixels(table.data(), 1, 1, colours, 0, out);
    for (int ch = 0; ch < 3; ++ch) {
      ASSERT_EQ(out[ch], DivideBy255Rounded(w0 * rgb[ch] + w1 * rgb[3 + ch] + w2 * rgb[6 + ch]))
          << "trial " << trial << " channel " << ch;
    }
  }
}

TEST(PixelResolve, ShownTrianglesAreNumberedInDrawOrder) {
  const uint8_t seen[6] = {0, 1, 1, 0, 0, 1};
  uint16_t slot[6];
  EXPECT_EQ(NumberShownTriangles(seen, 6, slot), 3u);
  const uint16_t want[6] = {0xFFFF, 0, 1, 0xFFFF, 0xFFFF, 2};
  for (int t = 0; t < 6; ++t) EXPECT_EQ(slot[t], want[t]) << t;
}

TEST(PixelResolve, AFrameIsEachPixelsWeightedVertexColoursTopRowFirst) {
  // 3 x 2 pixels; GL row 0 (the table's first) is the frame's bottom row.
  constexpr int kW = 3, kH = 2;
  std::vector<uint8_t> table(kW * kH * 4);
  const uint32_t shown[6] = {0, 1, 2, 2, 1, 3};  // slot 0: vertices 0 1 2; slot 1: 2 1 3
  const uint8_t rgb[12] = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30};
  Put(&table, 0, kResolveBackground);                 // bottom left
  Put(&table, 1, 0u | 0u << 16 | 0u << 24);           // slot 0, all first vertex
  Put(&table, 2, 0u | 255u << 16 | 0u << 24);         // slot 0, all second vertex
  Put(&table, 3, 1u | 0u << 16 | 255u << 24);         // top left: slot 1, all third vertex (3)
  Put(&table, 4, 0u | 85u << 16 | 85u << 24);         // slot 0, a third each
  Put(&table, 5, 1u | 100u << 16 | 55u << 24);        // slot 1: 100/255 of vertex 1, 55/255 of 3, the rest of 2
  std::vector<uint8_t> out(kW * kH * 3, 7);
  uint64_t slot_colours[6];
  GatherSlotColours(shown, 2, rgb, slot_colours);
  EXPECT_EQ(slot_colours[5], SpreadRgb(rgb + 9));
  ResolvePixels(table.data(), kW, kH, slot_colours, 32, out.data());
  const uint8_t want[kH][kW][3] = {
      {{10, 20, 30}, {85, 85, 85}, {2, 104, 106}},  // top row: GL row 1
      {{32, 32, 32}, {255, 0, 0}, {0, 255, 0}},    // bottom row: GL row 0
  };
  for (int y = 0; y < kH; ++y) {
    for (int x = 0; x < kW; ++x) {
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_EQ(out[(y * kW + x) * 3 + ch], want[y][x][ch]) << x << "," << y << " channel " << ch;
      }
    }
  }
}

// The AVX2 body against the scalar one: random tables (a fifth of the
// pixels background, weights anywhere in range) at widths around its
// four-pixel step, every byte the same, nothing written past the frame; and
// a row range writes its rows' bytes and nothing else (threads share frames).
TEST(PixelResolve, TheAvx2BodyWritesTheScalarBodysBytes) {
  std::mt19937 rng(9);
  constexpr uint32_t kSlots = 300;
  std::vector<uint64_t> colours(3 * kSlots);
  for (uint64_t& c : colours) {
    const uint8_t rgb[3] = {static_cast<uint8_t>(rng()), static_cast<uint8_t>(rng()), static_cast<uint8_t>(rng())};
    c = SpreadRgb(rgb);
  }
  int compared = 0;
  for (int width : {1, 2, 3, 4, 5, 7, 8, 9, 13, 64, 101}) {
    for (int height : {1, 2, 5}) {
      std::vector<uint8_t> table(static_cast<size_t>(width) * height * 4);
      for (size_t p = 0; p < table.size() / 4; ++p) {
        const uint32_t w1 = static_cast<uint32_t>(rng() % 256);
        const uint32_t w2 = static_cast<uint32_t>(rng() % (256 - w1));
        const uint32_t slot = rng() % 5 == 0 ? kResolveBackground : static_cast<uint32_t>(rng() % kSlots);
        Put(&table, p, slot | w1 << 16 | w2 << 24);
      }
      constexpr size_t kGuard = 16;
      const size_t bytes = static_cast<size_t>(width) * height * 3;
      std::vector<uint8_t> scalar(bytes + kGuard, 0xA5), avx2(bytes + kGuard, 0xA5);
      ASSERT_TRUE(ResolveRowsWith(ResolveBody::kScalar, table.data(), width, height, 0, height, colours.data(), 32,
                                  scalar.data()));
      if (!ResolveRowsWith(ResolveBody::kAvx2, table.data(), width, height, 0, height, colours.data(), 32,
                           avx2.data())) {
        GTEST_SKIP() << "no AVX2 on this CPU or target: the scalar body is the only one";
      }
      ASSERT_EQ(scalar, avx2) << width << " x " << height;
      for (size_t i = bytes; i < bytes + kGuard; ++i) ASSERT_EQ(avx2[i], 0xA5) << "written past the frame";
      // Each row on its own, into a frame where every other row is a guard:
      // the same bytes, and nothing written outside the row.
      for (ResolveBody body : {ResolveBody::kScalar, ResolveBody::kBest}) {
        for (int y = 0; y < height; ++y) {
          std::vector<uint8_t> one(bytes + kGuard, 0xA5);
          ASSERT_TRUE(ResolveRowsWith(body, table.data(), width, height, y, y + 1, colours.data(), 32, one.data()));
          const size_t row_bytes = static_cast<size_t>(width) * 3;
          for (size_t i = 0; i < one.size(); ++i) {
            const bool in_row = i / row_bytes == static_cast<size_t>(y) && i < bytes;
            ASSERT_EQ(one[i], in_row ? scalar[i] : 0xA5) << width << " x " << height << ", row " << y << ", byte " << i;
          }
        }
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, 33);
}

}  // namespace
}  // namespace relight::render
