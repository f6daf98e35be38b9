// The later bounces of coarse sources, tabulated at Open (issue 15,
// surface_emitter_bounces.h): the sources cut every tree once, within the
// area and the memory budget; a placement adds each covered source's stored
// bounces by its covered share; and a new light started from the table ends
// where one without it does, in fewer sweeps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "relight/baker/baker.h"
#include "relight/engine/engine.h"
#include "surface_emitter_bounces.h"
#include "surface_emitter_box.h"
#include "surface_emitter_test_support.h"
#include "test_scenes.h"

namespace relight::testing {
namespace {

bool IsUnder(const BakeHierarchy& h, uint32_t node, uint32_t ancestor) {
  for (uint32_t k = node; k != kBakeNoIndex; k = h.node_parent[k])
    if (k == ancestor) return true;
  return false;
}

uint32_t LeafCount(const BakeHierarchy& h) {
  uint32_t leaves = 0;
  for (uint32_t k = 0; k < h.node_count(); ++k) leaves += h.leaf(k) ? 1 : 0;
  return leaves;
}

// Every leaf in exactly one source, the source its ancestor (or itself);
// each source within the area unless it is a leaf, and as large as that
// allows (its parent is over the area).
void CheckCut(const BakeHierarchy& h, const EmitterBounceTable& table, int64_t max_area) {
  std::vector<int> times(h.node_count(), 0);
  std::vector<int64_t> coverage(h.node_count());
  for (uint32_t j = 0; j < table.source_count(); ++j) {
    const uint32_t s = table.source_node(j);
    if (!h.leaf(s)) {
      EXPECT_LE(h.node_area[s], static_cast<uint64_t>(max_area)) << "source " << j;
    }
    if (h.node_parent[s] != kBakeNoIndex) {
      EXPECT_GT(h.node_area[h.node_parent[s]], static_cast<uint64_t>(max_area)) << "source " << j;
    }
    table.UnitCoverage(j, coverage.data());
    for (uint32_t k = 0; k < h.node_count(); ++k) {
      if (coverage[k] == 0) continue;
      EXPECT_TRUE(h.leaf(k));
      EXPECT_EQ(coverage[k], int64_t{1} << 32);
      EXPECT_TRUE(IsUnder(h, k, s)) << "leaf " << k << " source node " << s;
      ++times[k];
    }
  }
  for (uint32_t k = 0; k < h.node_count(); ++k) {
    if (h.leaf(k)) {
      EXPECT_EQ(times[k], 1) << "leaf " << k;
    }
  }
}

TEST(EmitterBounceTable, SourcesCutEveryTreeOnceWithinTheAreaAndTheBudget) {
  const BakeHierarchy& h = *EmitterBoxBake().hierarchy;
  const int64_t per_source = int64_t{LeafCount(h)} * 6;
  EmitterBounceTable table;
  // The box's faces are 1 m^2: a quarter of that cuts each face in pieces.
  const int64_t quarter = int64_t{1} << 30;
  table.Partition(h, int64_t{1} << 40, UINT32_MAX, quarter);
  const uint32_t fine = table.source_count();
  EXPECT_GT(fine, 6u);
  EXPECT_EQ(table.bytes(), static_cast<size_t>(per_source) * fine);
  CheckCut(h, table, quarter);
  // A budget one byte short of that table: the area doubles until it fits.
  table.Partition(h, per_source * fine - 1, UINT32_MAX, quarter);
  EXPECT_LT(table.source_count(), fine);
  EXPECT_LE(static_cast<int64_t>(table.bytes()), per_source * fine - 1);
  EXPECT_GE(table.source_count(), 6u);
  // At most half the sources: the area doubles as for the budget.
  table.Partition(h, int64_t{1} << 40, fine / 2, quarter);
  EXPECT_LE(table.source_count(), fine / 2);
  EXPECT_GE(table.source_count(), 6u);
  // Not even one source per face fits: no table.
  table.Partition(h, per_source * 6 - 1, UINT32_MAX, quarter);
  EXPECT_EQ(table.source_count(), 0u);
  EXPECT_EQ(table.bytes(), 0u);
  std::vector<int64_t> b(3 * size_t{h.node_count()}, 7), coverage(h.node_count(), int64_t{1} << 32);
  EXPECT_EQ(table.AddTo(coverage.data(), 0, b.data()), nullptr);
  EXPECT_TRUE(std::all_of(b.begin(), b.end(), [](int64_t v) { return v == 7; }));
  table.Partition(h, 0, UINT32_MAX, quarter);
  EXPECT_EQ(table.source_count(), 0u);
}

// Stored bounces come back, per leaf and channel, times the covered share of
// their source: all of it, half of it (half the leaves covered fully, or all
// of them at half), nothing for an uncovered source.
TEST(EmitterBounceTable, APlacementAddsEachSourcesBouncesByItsCoveredShare) {
  const BakeHierarchy& h = *EmitterBoxBake().hierarchy;
  const uint32_t n = h.node_count();
  EmitterBounceTable table;
  table.Partition(h, int64_t{1} << 40, UINT32_MAX, int64_t{1} << 30);
  ASSERT_GT(table.source_count(), 2u);
  // Source j's bounces: distinct values per leaf and channel, up to 2^40.
  std::vector<int64_t> start(3 * size_t{n}, 0), solved(3 * size_t{n}, 0);
  const auto value = [](uint32_t j, uint32_t k, int ch) {
    return (int64_t{1} << 40) / (1 + (k * 7 + static_cast<uint32_t>(ch) * 3 + j) % 97) * (k % 5 == 0 ? -1 : 1);
  };
  SweepContraction seen;
  seen.valid = true;
  for (uint32_t j = 0; j < table.source_count(); ++j) {
    for (uint32_t k = 0; k < n; ++k)
      for (int ch = 0; ch < 3; ++ch) solved[3 * size_t{k} + ch] = start[3 * size_t{k} + ch] + value(j, k, ch);
    seen.change[0] = j;
    table.Store(j, solved.data(), start.data(), seen);
  }
  const uint32_t j = 1, node = table.source_node(j);
  uint32_t root = node;
  while (h.node_parent[root] != kBakeNoIndex) root = h.node_parent[root];
  std::vector<int64_t> full(n, 0), half_each(n, 0);
  table.UnitCoverage(j, full.data());
  for (uint32_t k = 0; k < n; ++k) half_each[k] = full[k] / 2;
  // Quantised to 15 bits of the largest value (2^40): within 2^26 each.
  const int64_t step = int64_t{1} << 26;
  for (const std::vector<int64_t>* cov : {&full, &half_each}) {
    std::vector<int64_t> b(3 * size_t{n}, 1000);
    const SweepContraction* hint = table.AddTo(cov->data(), root, b.data());
    ASSERT_NE(hint, nullptr);
    EXPECT_EQ(hint->change[0], j) << "the covered source's contraction";
    const double share = cov == &full ? 1.0 : 0.5;
    for (uint32_t k = 0; k < n; ++k)
      for (int ch = 0; ch < 3; ++ch) {
        const double want = h.leaf(k) ? 1000 + share * static_cast<double>(value(j, k, ch)) : 1000;
        EXPECT_NEAR(static_cast<double>(b[3 * size_t{k} + ch]), want, step) << "node " << k << " channel " << ch;
      }
  }
  // Nothing covered: nothing added, no hint.
  std::vector<int64_t> none(n, 0), b(3 * size_t{n}, 5);
  EXPECT_EQ(table.AddTo(none.data(), root, b.data()), nullptr);
  EXPECT_TRUE(std::all_of(b.begin(), b.end(), [](int64_t v) { return v == 5; }));
}

// New lights, FE and AR, with the table (the default) and without: the
// same light to the solver's tolerance (2^-11 of peak), in fewer sweeps.
TEST(SurfaceEmitterBounces, ANewLightStartedFromTheTableEndsWhereOneWithoutItDoesInFewerSweeps) {
  EngineOptions without_table, with_table;
  without_table.emitter_bounce_table_bytes = 0;
  with_table.emitter_quick_changes = false;  // solved at once: the sweeps are what is compared
  Engine with, without;
  ASSERT_TRUE(with.Open(Bake(EmitterBoxBake()), with_table).ok());
  ASSERT_TRUE(without.Open(Bake(EmitterBoxBake()), without_table).ok());
  for (Engine* e : {&with, &without})
    for (int i = 0; i < e->luminaire_count(); ++i) ASSERT_TRUE(e->SetDimmer(i, Q1_15::FromRaw(0)).ok());
  const LightQ12 light[3] = {Light(300), Light(250), Light(200)};
  const std::vector<std::vector<Vec3>> shapes = {
      {{0.31, 0.29, 1}, {0.63, 0.33, 1}, {0.47, 0.66, 1}},
      {{0.05, 0.1, 1}, {0.95, 0.1, 1}, {0.95, 0.6, 1}, {0.05, 0.6, 1}},
  };
  int sweeps_with = 0, sweeps_without = 0;
  for (const SurfaceEmitterMethod method :
       {SurfaceEmitterMethod::kFractionalEmissivity, SurfaceEmitterMethod::kAdaptiveRefine}) {
    for (const std::vector<Vec3>& corners : shapes) {
      SurfaceEmitterShape shape = MakeShape("ceiling", corners);
      shape.method = method;
      for (Engine* e : {&with, &without}) {
        ASSERT_TRUE(e->RemoveSurfaceEmitter(0).ok());
        e->Update();
        ASSERT_TRUE(e->SetSurfaceEmitter(0, shape, light).ok());
        e->Update();
        ASSERT_EQ(e->last_update_emitters_solved(), 1);
      }
      sweeps_with += with.last_update_emitter_sweeps();
      sweeps_without += without.last_update_emitter_sweeps();
      const std::vector<int32_t> a = Luminance(with), b = Luminance(without);
      int64_t peak = 0, max_diff = 0, sum_diff = 0;
      for (size_t i = 0; i < a.size(); ++i) {
        peak = std::max<int64_t>(peak, b[i]);
        max_diff = std::max<int64_t>(max_diff, std::llabs(int64_t{a[i]} - b[i]));
        sum_diff += std::llabs(int64_t{a[i]} - b[i]);
      }
      ASSERT_GT(peak, 0);
      const double max_rel = static_cast<double>(max_diff) / static_cast<double>(peak);
      const double mean_rel = static_cast<double>(sum_diff) / static_cast<double>(a.size()) / static_cast<double>(peak);
      std::printf("[ measured ] %s, %zu corners: with the table %d sweeps, without %d; max %.2e mean %.2e of peak\n",
                  method == SurfaceEmitterMethod::kAdaptiveRefine ? "AR" : "FE", corners.size(),
                  with.last_update_emitter_sweeps(), without.last_update_emitter_sweeps(), max_rel, mean_rel);
      EXPECT_LE(max_rel, 1e-3);
      EXPECT_LE(mean_rel, 1e-4);
    }
  }
  EXPECT_LT(sweeps_with, sweeps_without);
}

}  // namespace
}  // namespace relight::testing
