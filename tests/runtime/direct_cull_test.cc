// Skipping receivers a beam cannot reach (direct_cull.h): the LID's zero
// angle against its lookup, the cosine threshold against the acos table,
// and the aimed kernel with block culling against the same kernel without,
// bit for bit, on a floor in raster order under beams with a cut-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "direct_aimed.h"
#include "direct_cull.h"
#include "engine_test_support.h"
#include "gamma_table.h"
#include "lid_lookup.h"
#include "relight/bake/bake_limits.h"
#include "weights.h"

namespace relight {
namespace {

// M + 1 samples, non-zero up to `last` (the last one 1 LSB: the weakest
// tail), 0 after.
std::vector<int64_t> CutLid(int M, int last, std::mt19937_64* rng) {
  std::uniform_int_distribution<int64_t> cd(1, bake_format::kMaxCandelaRaw);
  std::vector<int64_t> lid(static_cast<size_t>(M) + 1, 0);
  for (int k = 0; k <= last; ++k) lid[static_cast<size_t>(k)] = cd(*rng);
  if (last >= 0) lid[static_cast<size_t>(last)] = 1;
  return lid;
}

TEST(DirectCull, LidIsZeroFromItsZeroAngleOn) {
  std::mt19937_64 rng(5);
  for (int M : {1, 7, 180, 720}) {
    for (int last : {-1, 0, 1, M / 3, M - 1, M}) {
      if (last < -1 || last > M) continue;
      const std::vector<int64_t> lid = CutLid(M, last, &rng);
      const uint64_t g_zero = LidZeroFromBam(lid.data(), M);
      if (last == M) {
        EXPECT_EQ(g_zero, uint64_t{1} << 32);
        continue;
      }
      ASSERT_LE(g_zero, uint64_t{1} << 31) << "M " << M << " last " << last;
      std::uniform_int_distribution<uint64_t> past(g_zero, uint64_t{1} << 31);
      for (int i = 0; i < 2000; ++i) {
        const Bam g = static_cast<Bam>(i == 0 ? g_zero : past(rng));
        ASSERT_EQ(LidIntensityFastQ16(lid.data(), M, g), 0) << "M " << M << " last " << last << " g " << g;
      }
      // Tight: one BAM before it the lookup is still on the last sample's segment.
      if (g_zero > 0) {
        const uint64_t index = ((uint64_t{g_zero - 1} * static_cast<uint64_t>(M) + (1u << 14)) >> 15) >> 16;
        EXPECT_EQ(index, static_cast<uint64_t>(last)) << "M " << M;
      }
    }
  }
}

TEST(DirectCull, ZeroCosineIsTheTablesBoundary) {
  const GammaTable& t = SharedGammaTable();
  // The table's map is non-increasing in cos (the threshold rests on it):
  // a sweep across [-1, 1] in Q2.60, dense near -1, 0 and 1.
  std::mt19937_64 rng(8);
  std::vector<int64_t> cs;
  for (int e = 0; e <= 61; ++e) {
    for (int64_t base : {-(int64_t{1} << 60), int64_t{0}, int64_t{1} << 60}) {
      cs.push_back(base + (int64_t{1} << e) - 1);
      cs.push_back(base - (int64_t{1} << e) + 1);
    }
  }
  std::uniform_int_distribution<int64_t> any(-(int64_t{1} << 61), int64_t{1} << 61);
  for (int i = 0; i < 200000; ++i) cs.push_back(any(rng));
  std::sort(cs.begin(), cs.end());
  for (size_t i = 1; i < cs.size(); ++i) {
    ASSERT_GE(GammaFromCosQ60(t, cs[i - 1]), GammaFromCosQ60(t, cs[i])) << cs[i - 1] << " " << cs[i];
  }
  std::uniform_int_distribution<uint64_t> g(1, uint64_t{1} << 31);
  for (int i = 0; i < 500; ++i) {
    const uint64_t g_zero = i == 0 ? 1 : (i == 1 ? uint64_t{1} << 31 : g(rng));
    const int64_t c = ZeroCosQ60(t, g_zero);
    ASSERT_GE(GammaFromCosQ60(t, c), g_zero);
    ASSERT_LT(GammaFromCosQ60(t, c + 1), g_zero);
  }
  EXPECT_EQ(ZeroCosQ60(t, 0), std::numeric_limits<int64_t>::max());
  EXPECT_EQ(ZeroCosQ60(t, uint64_t{1} << 32), std::numeric_limits<int64_t>::min());
}

// A 40 x 40 m floor 6 m under a head, receivers in raster order (as a
// mesher's are: neighbours in the list are neighbours on the floor), a
// few with no geometry.
struct Floor {
  std::vector<int16_t> direction;
  std::vector<uint32_t> geometry;
  std::vector<uint32_t> rho;
  DirectPoints points;
  uint32_t n = 0;
};

// blank_rows: rows [0, blank_rows) get no geometry either (a strip no
// luminaire sees: whole blocks of it keep no points).
Floor MakeFloor(int side, int blank_rows = 0) {
  Floor f;
  f.n = static_cast<uint32_t>(side * side);
  for (int y = 0; y < side; ++y) {
    for (int x = 0; x < side; ++x) {
      const double d[3] = {-20.0 + 40.0 * x / (side - 1), -20.0 + 40.0 * y / (side - 1), -6.0};
      const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      for (double c : d) f.direction.push_back(static_cast<int16_t>(std::lround(c / len * 16384)));
      const bool none = (x * 7 + y) % 97 == 0 || y < blank_rows;
      f.geometry.push_back(none ? 0u : static_cast<uint32_t>(6.0 / (len * len * len) * 4e9));
    }
  }
  std::vector<uint16_t> albedo(static_cast<size_t>(f.n) * 3);
  for (size_t i = 0; i < albedo.size(); ++i) albedo[i] = static_cast<uint16_t>(3000 + 7919 * i % 62000);
  f.rho.resize(albedo.size());
  ReflectanceOverPiQ32(albedo.data(), static_cast<uint32_t>(albedo.size()), f.rho.data());
  const DirectReceivers rx{f.direction.data(), f.geometry.data(), QuantScale{1 << 29, -31}, f.n};
  PrepareDirectPoints(rx, &f.points);
  return f;
}

TEST(DirectCull, SkippedBlocksGiveTheSameValues) {
  Floor f = MakeFloor(150);
  DirectPoints unculled = f.points;  // every block's cone wider than any beam
  for (DirectBlock& b : unculled.blocks) {
    if (b.half_angle != kNoPoints) b.half_angle = uint32_t{1} << 31;  // an empty block has no points to read
  }
  const GammaTable& t = SharedGammaTable();
  std::mt19937_64 rng(21);
  int skipped = 0, blocks = 0;
  int64_t lit = 0;
  // Beam edges at 4 .. 80 degrees off axis (M = 180: a sample a degree).
  for (int last : {3, 12, 40, 80}) {
    const std::vector<int64_t> lid = CutLid(180, last, &rng);
    const uint64_t g_zero = LidZeroFromBam(lid.data(), 180);
    const int64_t zero_cos = ZeroCosQ60(t, g_zero);
    for (double tilt : {0.0, 20.0, 55.0, 89.0, 120.0}) {
      for (double pan : {0.0, 70.0, -150.0}) {
        int32_t axis[3];
        BeamAxisQ30(Mounting::kHanging, Q16_16::FromRatio(std::llround(pan * 1000), 1000),
                    Q16_16::FromRatio(std::llround(tilt * 1000), 1000), axis);
        for (const DirectBlock& b : f.points.blocks) {
          ++blocks;
          if (BlockOutsideBeam(b, t, axis, g_zero)) ++skipped;
        }
        // Every receiver at or below the cosine threshold is one the LID gives 0.
        for (const DirectPoint& p : f.points.points) {
          const int64_t c = int64_t{p.direction_q30[0]} * axis[0] + int64_t{p.direction_q30[1]} * axis[1] +
                            int64_t{p.direction_q30[2]} * axis[2];
          if (c <= zero_cos) {
            ASSERT_EQ(LidIntensityFastQ16(lid.data(), 180, GammaFromCosQ60(t, c)), 0);
          }
        }
        const uint32_t* rhos[2] = {f.rho.data(), nullptr};
        for (const uint32_t* rho : rhos) {
          for (DirectStore store : {DirectStore::kWrite, DirectStore::kAdd}) {
            std::vector<int32_t> a(static_cast<size_t>(f.n) * 3, 77), b = a;
            DirectLightAimedQ12(f.points, t, axis, lid.data(), 180, rho, store, a.data());
            DirectLightAimedQ12(unculled, t, axis, lid.data(), 180, rho, store, b.data());
            ASSERT_EQ(a, b) << "last " << last << " tilt " << tilt << " pan " << pan;
            for (size_t i = 0; i < a.size(); ++i) lit += a[i] != 77 && a[i] != 0 ? 1 : 0;
          }
        }
      }
    }
  }
  std::printf("  %d of %d blocks skipped, %lld values lit\n", skipped, blocks, static_cast<long long>(lit));
  EXPECT_GT(skipped, blocks / 4);  // the test must exercise the skip
  EXPECT_GT(lit, 100000);          // and compare light, not only zeros
}

TEST(DirectCull, BlocksNoLightReachesKeepNoPointsAndGiveZero) {
  constexpr int kSide = 150, kBlank = 40;  // 6000 receivers unseen: 187 whole blocks
  const Floor blank = MakeFloor(kSide, kBlank), full = MakeFloor(kSide);
  size_t empty = 0;
  for (const DirectBlock& b : blank.points.blocks) empty += b.half_angle == kNoPoints ? 1 : 0;
  EXPECT_GE(empty, size_t{kSide * kBlank / kDirectBlockPoints - 1});
  EXPECT_EQ(blank.points.count, blank.n);
  EXPECT_EQ(blank.points.points.size(), size_t{blank.n} - empty * kDirectBlockPoints);
  EXPECT_EQ(blank.points.shift, full.points.shift);  // the brightest receiver is seen in both
  const GammaTable& t = SharedGammaTable();
  std::mt19937_64 rng(5);
  const std::vector<int64_t> lid = CutLid(180, 60, &rng);
  int64_t lit = 0;
  for (double tilt : {0.0, 40.0, 80.0}) {
    int32_t axis[3];
    BeamAxisQ30(Mounting::kHanging, Q16_16::FromRatio(0, 1), Q16_16::FromRatio(std::llround(tilt * 1000), 1000),
                axis);
    for (DirectStore store : {DirectStore::kWrite, DirectStore::kAdd}) {
      std::vector<int32_t> a(static_cast<size_t>(blank.n) * 3, 77), b = a;
      DirectLightAimedQ12(blank.points, t, axis, lid.data(), 180, blank.rho.data(), store, a.data());
      DirectLightAimedQ12(full.points, t, axis, lid.data(), 180, full.rho.data(), store, b.data());
      for (uint32_t i = 0; i < blank.n; ++i) {
        for (int c = 0; c < 3; ++c) {
          const size_t k = size_t{i} * 3 + static_cast<size_t>(c);
          if (i < uint32_t{kSide * kBlank}) {
            ASSERT_EQ(a[k], store == DirectStore::kWrite ? 0 : 77) << "unseen receiver " << i;
          } else {
            ASSERT_EQ(a[k], b[k]) << "receiver " << i << " tilt " << tilt;
            lit += b[k] != 0 && b[k] != 77 ? 1 : 0;
          }
        }
      }
    }
  }
  EXPECT_GT(lit, 10000);  // the seen receivers' values are light, not only zeros
}

}  // namespace
}  // namespace relight
