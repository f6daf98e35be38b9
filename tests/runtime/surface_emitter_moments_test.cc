// The emitter solve's source-moment gathers (surface_emitter_moments.h): the
// AVX2 body gives the scalar path's bits on random data at the bounds the
// solve allows, and the table follows the baker's rule.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "surface_emitter_gather_avx2.h"
#include "surface_emitter_moments.h"

namespace relight {
namespace {

TEST(SurfaceEmitterMoments, Avx2GatherIsBitIdenticalToScalar) {
  if (!EmitterGatherHasAvx2()) GTEST_SKIP() << "no AVX2 here (or RELIGHT_FORCE_SCALAR)";
  std::mt19937 rng(15);
  constexpr uint32_t kInner = 64;
  std::vector<int32_t> moment(8 * kInner);
  // The moment view is saturated to +-2^31 + 1 at most (view_limit_).
  std::uniform_int_distribution<int32_t> any(-INT32_MAX, INT32_MAX);
  for (int trial = 0; trial < 200; ++trial) {
    for (uint32_t i = 0; i < 8 * kInner; ++i) moment[i] = (i % 4 == 3) ? 0 : any(rng);
    // Up to 16 terms of full-range weights: |sum| < 16 x 2^62 would overflow,
    // so the weights are scaled as Init's bound would (sum |w| x limit < 2^63).
    const uint32_t count = static_cast<uint32_t>(trial % 17);
    std::vector<EmitterMomentEntry> e(count);
    std::uniform_int_distribution<int32_t> weight(-(INT32_MAX >> 5), INT32_MAX >> 5);
    for (EmitterMomentEntry& x : e) x = {static_cast<uint32_t>(rng() % kInner), weight(rng), weight(rng)};
    int64_t scalar[3] = {1, 2, 3}, vector[3] = {4, 5, 6};
    GatherMoment(e.data(), count, moment.data(), scalar);
    GatherMomentAvx2(e.data(), count, moment.data(), vector);
    for (int c = 0; c < 3; ++c) ASSERT_EQ(scalar[c], vector[c]) << "trial " << trial << " channel " << c;
    if (count == 0) {
      EXPECT_EQ(scalar[0], 0);
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
