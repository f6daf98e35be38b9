// The emitter solve's source-moment gathers (surface_emitter_moments.h): the
// AVX2 bodies of the gathers from inner sources give the scalar path's bits
// on random data at the bounds the solve allows, and the table follows the
// baker's rule.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "surface_emitter_gather.h"
#include "surface_emitter_gather_avx2.h"
#include "surface_emitter_moments.h"

namespace relight {
namespace {

// The gathers from inner sources read a row of exitance and moment per
// source (kInnerRowInts) with the factor and both moment weights in one
// entry; the AVX2 bodies must give the scalar sums, for leaf and inner
// receivers, adding to what the leaf sources already put in a, u and v.
TEST(SurfaceEmitterMoments, InnerSourceGathersAreBitIdenticalToScalar) {
  if (!EmitterGatherHasAvx2()) GTEST_SKIP() << "no AVX2 here (or RELIGHT_FORCE_SCALAR)";
  std::mt19937 rng(15);
  constexpr uint32_t kInner = 64;
  std::vector<int32_t> rows(kInnerRowInts * kInner);
  // Views are saturated to +-(2^31 - 1) at most (view_limit_).
  std::uniform_int_distribution<int32_t> any(-INT32_MAX, INT32_MAX);
  for (int trial = 0; trial < 200; ++trial) {
    for (uint32_t i = 0; i < rows.size(); ++i) rows[i] = (i % 4 == 3 || i % kInnerRowInts >= 12) ? 0 : any(rng);
    // Up to 16 terms: factors and weights scaled as Init's bound would keep
    // the sums below 2^63 (sum x limit < 2^63).
    const uint32_t count = static_cast<uint32_t>(trial % 17);
    std::vector<EmitterInnerSourceEntry> e(count);
    std::vector<int32_t> g(2 * size_t{count});
    std::uniform_int_distribution<int32_t> weight(-(INT32_MAX >> 5), INT32_MAX >> 5);
    std::uniform_int_distribution<uint32_t> factor(0, (uint32_t{1} << 27));
    for (EmitterInnerSourceEntry& x : e)
      x = {static_cast<uint32_t>(rng() % kInner), factor(rng), weight(rng), weight(rng)};
    for (int32_t& x : g) x = weight(rng);
    int64_t a[2][3] = {{1, -2, 3}, {1, -2, 3}}, m[2][3] = {{7, 7, 7}, {8, 8, 8}};
    GatherLeafFromInner(e.data(), count, rows.data(), a[0], m[0]);
    GatherLeafFromInnerAvx2(e.data(), count, rows.data(), a[1], m[1]);
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(a[0][c], a[1][c]) << "leaf receiver, trial " << trial << " channel " << c;
      ASSERT_EQ(m[0][c], m[1][c]) << "leaf receiver, trial " << trial << " channel " << c;
    }
    int64_t b[2][3] = {{4, 5, -6}, {4, 5, -6}}, u[2][3] = {{9, 9, 9}, {9, 9, 9}}, v[2][3] = {{-1, 0, 1}, {-1, 0, 1}};
    GatherInnerFromInner(e.data(), g.data(), count, rows.data(), b[0], u[0], v[0], m[0]);
    GatherInnerFromInnerAvx2(e.data(), g.data(), count, rows.data(), b[1], u[1], v[1], m[1]);
    for (int c = 0; c < 3; ++c) {
      ASSERT_EQ(b[0][c], b[1][c]) << "inner receiver, trial " << trial << " channel " << c;
      ASSERT_EQ(u[0][c], u[1][c]) << "inner receiver, trial " << trial << " channel " << c;
      ASSERT_EQ(v[0][c], v[1][c]) << "inner receiver, trial " << trial << " channel " << c;
      ASSERT_EQ(m[0][c], m[1][c]) << "inner receiver, trial " << trial << " channel " << c;
    }
    if (count == 0) {  // nothing added, the moment sum zero
      EXPECT_EQ(a[0][1], -2);
      EXPECT_EQ(m[0][0], 0);
    } else {  // the scalar sum itself, for the first channel
      int64_t want = 1, want_m = 0;
      for (const EmitterInnerSourceEntry& x : e) {
        const int32_t* row = &rows[kInnerRowInts * size_t{x.source}];
        want += int64_t{x.f} * row[0];
        want_m += int64_t{x.wu} * row[4] + int64_t{x.wv} * row[8];
      }
      EXPECT_EQ(a[0][0], want);
      EXPECT_EQ(b[1][0] - 4, want - 1);
      EXPECT_EQ(m[1][0], want_m);
    }
  }
}

// Surface 0: a root (0) with two leaf children; surface 1: one leaf (3).
// Link 0 (0, 3) both ways; link 1 (0, 3) again with no reverse factor
// (f_pq = 0): no moment term for it.
TEST(SurfaceEmitterMoments, TermsWhereTheSourceIsAnInnerNodeWithAReverseFactor) {
  BakeHierarchy h;
  h.node_surface = {0, 0, 0, 1};
  h.node_parent = {kBakeNoIndex, 0, 0, kBakeNoIndex};
  h.node_first_child = {1, kBakeNoIndex, kBakeNoIndex, kBakeNoIndex};
  h.node_child_count = {2, 0, 0, 0};
  h.link_p = {0, 0};
  h.link_q = {3, 3};
  h.link_f_pq = {1u << 28, 0};
  h.link_f_qp = {1u << 30, 1u << 29};
  // The gradient over node 0 (the reverse of 3's gathers): 8 per metre along
  // u (Q23), -4 along v.
  h.link_g_pq = {1 << 26, -(1 << 25), 0, 0};
  h.link_g_qp = {0, 0, 0, 0};
  EmitterMomentTable t;
  BuildEmitterMoments(h, &t);
  ASSERT_EQ(t.offsets.size(), 5u);
  // Only node 3 gathers from an inner node (0), through link 0.
  EXPECT_EQ(t.offsets[3], 0u);
  EXPECT_EQ(t.offsets[4], 1u);
  ASSERT_EQ(t.entries.size(), 1u);
  EXPECT_EQ(t.entries[0].source, 0u);  // node 0 is the first inner node
  // w = f g_rev / f_rev = 2^30 x 8 / 2^28 = 32 per metre, Q36 = 2^41: shift 11.
  EXPECT_EQ(t.shift, 11);
  EXPECT_EQ(t.entries[0].wu, 1 << 30);
  EXPECT_EQ(t.entries[0].wv, -(1 << 29));
  EXPECT_EQ(EmitterMomentRowSum(t, 3), (uint64_t{3} << 29) << 11);
  EXPECT_EQ(EmitterMomentRowSum(t, 1), 0u);
}

}  // namespace
}  // namespace relight
