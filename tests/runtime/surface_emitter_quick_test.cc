// Answer now, settle later (issue 15; surface_emitters.h): an adaptive-refine
// move is shown from its start (the previous solution, the exact
// change of emission and first bounce, the later-bounce table's change)
// without a sweep, near where it was last solved in full; an Update() that changes no
// emitter then solves it in full. The quick answers are measured against a
// solve from nothing, and so is what they settle to.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "relight/engine/engine.h"
#include "surface_emitter_bounces.h"
#include "surface_emitter_box.h"
#include "surface_emitter_test_support.h"

namespace relight::testing {
namespace {

const LightQ12 kLight[3] = {Light(300), Light(250), Light(200)};

SurfaceEmitterShape Ceiling(double dx, double dy) {
  return MakeShape("ceiling", {{0.31 + dx, 0.29 + dy, 1}, {0.63 + dx, 0.33 + dy, 1}, {0.47 + dx, 0.66 + dy, 1}});
}

// Largest and mean |a - b| over the vertices, as fractions of b's peak.
void Gap(const std::vector<int32_t>& a, const std::vector<int32_t>& b, double* max_rel, double* mean_rel) {
  int64_t peak = 0, worst = 0, sum = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    peak = std::max<int64_t>(peak, b[i]);
    const int64_t d = std::llabs(int64_t{a[i]} - b[i]);
    worst = std::max(worst, d);
    sum += d;
  }
  ASSERT_GT(peak, 0);
  *max_rel = static_cast<double>(worst) / static_cast<double>(peak);
  *mean_rel = static_cast<double>(sum) / static_cast<double>(a.size()) / static_cast<double>(peak);
}

// The light of the place at (dx, dy) solved from nothing (no table, no quick answer).
std::vector<int32_t> FromNothing(Engine* placed, double dx, double dy) {
  EXPECT_TRUE(placed->RemoveSurfaceEmitter(0).ok());
  placed->Update();
  EXPECT_TRUE(placed->SetSurfaceEmitter(0, Ceiling(dx, dy), kLight).ok());
  placed->Update();
  return Luminance(*placed);
}

class SurfaceEmitterQuick : public ::testing::Test {
 protected:
  void SetUp() override {
    EngineOptions from_nothing;
    from_nothing.emitter_bounce_table_bytes = 0;
    ASSERT_TRUE(dragged_.Open(Bake(EmitterBoxBake())).ok());  // the defaults: table and quick answers
    ASSERT_TRUE(placed_.Open(Bake(EmitterBoxBake()), from_nothing).ok());
    for (Engine* e : {&dragged_, &placed_})
      for (int i = 0; i < e->luminaire_count(); ++i) ASSERT_TRUE(e->SetDimmer(i, Q1_15::FromRaw(0)).ok());
    ASSERT_GT(dragged_.emitter_bounce_sources(), 0);
  }
  Engine dragged_, placed_;
};

// A drag of 2 mm steps (within quick reach: 1/32 of the table's source
// side, 6.8 mm in this 1 m box): every move a quick answer, within 2e-3 of peak
// max, 2e-4 mean of a solve from nothing (10 cm moves, every one quick,
// measured 1.0e-3 and 8.4e-5), and what it settles to within the solver's
// own bars (1e-3, 1e-4). A move beyond reach is solved in full.
TEST_F(SurfaceEmitterQuick, ADragNearItsAnchorIsAnsweredWithoutSweepsAndSettlesWhenIdle) {
  ASSERT_TRUE(dragged_.SetSurfaceEmitter(0, Ceiling(0, 0), kLight).ok());
  dragged_.Update();
  EXPECT_EQ(dragged_.last_update_emitters_quick(), 0);  // a new light is solved at once
  EXPECT_GE(dragged_.last_update_emitter_sweeps(), 1);
  EXPECT_TRUE(dragged_.emitters_settled());
  std::string kinds;
  double quick_max = 0, quick_mean = 0, full_max = 0, full_mean = 0;
  for (int step = 1; step <= 6; ++step) {
    const double dx = 0.002 * ((step / 2) % 2), dy = 0.002 * (((step + 1) / 2) % 2) + 0.0005 * step;
    ASSERT_TRUE(dragged_.SetSurfaceEmitter(0, Ceiling(dx, dy), kLight).ok());
    dragged_.Update();
    ASSERT_EQ(dragged_.last_update_emitters_solved(), 1);
    const bool quick = dragged_.last_update_emitters_quick() == 1;
    kinds += quick ? "q" : "F";
    EXPECT_EQ(dragged_.emitters_settled(), !quick);
    double max_rel = 0, mean_rel = 0;
    Gap(Luminance(dragged_), FromNothing(&placed_, dx, dy), &max_rel, &mean_rel);
    double& worst_max = quick ? quick_max : full_max;
    double& worst_mean = quick ? quick_mean : full_mean;
    worst_max = std::max(worst_max, max_rel);
    worst_mean = std::max(worst_mean, mean_rel);
  }
  std::printf("[ measured ] 2 mm drag, q = quick answer, F = full solve: %s; against solves from nothing: "
              "quick max %.2e mean %.2e of peak\n", kinds.c_str(), quick_max, quick_mean);
  EXPECT_EQ(kinds, "qqqqqq");
  EXPECT_LE(quick_max, 2e-3);
  EXPECT_LE(quick_mean, 2e-4);

  // One more quick move, then an idle Update settles it to a full solve's answer.
  const double dx = 0.002, dy = 0.004;
  ASSERT_TRUE(dragged_.SetSurfaceEmitter(0, Ceiling(dx, dy), kLight).ok());
  dragged_.Update();
  ASSERT_EQ(dragged_.last_update_emitters_quick(), 1);
  const std::vector<int32_t> quick = Luminance(dragged_);
  dragged_.Update();
  EXPECT_EQ(dragged_.last_update_emitters_solved(), 1);
  EXPECT_EQ(dragged_.last_update_emitters_quick(), 0);
  EXPECT_GE(dragged_.last_update_emitter_sweeps(), 1);
  EXPECT_TRUE(dragged_.emitters_settled());
  EXPECT_NE(Luminance(dragged_), quick);
  double max_rel = 0, mean_rel = 0;
  Gap(Luminance(dragged_), FromNothing(&placed_, dx, dy), &max_rel, &mean_rel);
  std::printf("[ measured ] settled after the drag: max %.2e mean %.2e of peak against a solve from nothing\n",
              max_rel, mean_rel);
  EXPECT_LE(max_rel, 1e-3);
  EXPECT_LE(mean_rel, 1e-4);
  // Settled is still: the next idle Update solves nothing and changes no bit.
  const std::vector<int32_t> settled = Luminance(dragged_);
  dragged_.Update();
  EXPECT_EQ(dragged_.last_update_emitters_solved(), 0);
  EXPECT_EQ(Luminance(dragged_), settled);
  // 10 cm on: beyond reach, solved at once.
  ASSERT_TRUE(dragged_.SetSurfaceEmitter(0, Ceiling(dx + 0.1, dy), kLight).ok());
  dragged_.Update();
  EXPECT_EQ(dragged_.last_update_emitters_solved(), 1);
  EXPECT_EQ(dragged_.last_update_emitters_quick(), 0);
  EXPECT_TRUE(dragged_.emitters_settled());
}

// Moved back onto its stored solution, the slot is anchored there again: a
// small step from it is a quick answer, though the last full solve was 10 cm off.
TEST_F(SurfaceEmitterQuick, AMoveBackAnchorsTheQuickAnswersWhereItRestored) {
  ASSERT_TRUE(dragged_.SetSurfaceEmitter(0, Ceiling(0, 0), kLight).ok());
  dragged_.Update();
  ASSERT_TRUE(dragged_.SetSurfaceEmitter(0, Ceiling(0.1, 0), kLight).ok());  // beyond reach: solved
  dragged_.Update();
  ASSERT_EQ(dragged_.last_update_emitters_quick(), 0);
  ASSERT_TRUE(dragged_.SetSurfaceEmitter(0, Ceiling(0, 0), kLight).ok());  // back: restored
  dragged_.Update();
  ASSERT_EQ(dragged_.last_update_emitters_solved(), 0);
  ASSERT_TRUE(dragged_.SetSurfaceEmitter(0, Ceiling(0.002, 0), kLight).ok());
  dragged_.Update();
  EXPECT_EQ(dragged_.last_update_emitters_quick(), 1);
}

// Quick answers need the table and the method: FE, no table, or the option
// off solve every change at once.
TEST_F(SurfaceEmitterQuick, OnlyAdaptiveRefineWithATableAndTheOptionOnAnswersQuickly) {
  SurfaceEmitterShape fe = Ceiling(0, 0);
  fe.method = SurfaceEmitterMethod::kFractionalEmissivity;
  ASSERT_TRUE(dragged_.SetSurfaceEmitter(1, fe, kLight).ok());
  dragged_.Update();
  EXPECT_EQ(dragged_.last_update_emitters_quick(), 0);
  EXPECT_GE(dragged_.last_update_emitter_sweeps(), 1);
  EXPECT_TRUE(dragged_.emitters_settled());

  ASSERT_TRUE(placed_.SetSurfaceEmitter(0, Ceiling(0, 0), kLight).ok());  // no table
  placed_.Update();
  ASSERT_TRUE(placed_.SetSurfaceEmitter(0, Ceiling(0.1, 0), kLight).ok());
  placed_.Update();
  EXPECT_EQ(placed_.last_update_emitters_quick(), 0);
  EXPECT_TRUE(placed_.emitters_settled());

  EngineOptions off;
  off.emitter_quick_changes = false;
  Engine at_once;
  ASSERT_TRUE(at_once.Open(Bake(EmitterBoxBake()), off).ok());
  ASSERT_TRUE(at_once.SetSurfaceEmitter(0, Ceiling(0, 0), kLight).ok());
  at_once.Update();
  ASSERT_TRUE(at_once.SetSurfaceEmitter(0, Ceiling(0.1, 0), kLight).ok());
  at_once.Update();
  EXPECT_EQ(at_once.last_update_emitters_quick(), 0);
  EXPECT_TRUE(at_once.emitters_settled());
}

// The table's change between two coverages is the table of the one minus
// the table of the other, and nothing where the covered share stays the same.
TEST(EmitterBounceTableChange, IsTheDifferenceOfTheTwoCoveragesTables) {
  const Bake& bake = EmitterBoxBake();
  const BakeHierarchy& h = *bake.hierarchy;
  EmitterBounceTable table;
  table.Partition(h, int64_t{64} << 20);
  ASSERT_GT(table.source_count(), 2u);
  const uint32_t n = h.node_count();
  std::vector<int64_t> a(n, 0), b(n, 0);
  table.UnitCoverage(0, a.data());
  table.UnitCoverage(1, b.data());
  // Fill the table with a pattern, as Store would from solves.
  std::vector<int64_t> solved(3 * size_t{n}, 0), start(3 * size_t{n}, 0);
  for (uint32_t j = 0; j < table.source_count(); ++j) {
    for (size_t i = 0; i < solved.size(); ++i) solved[i] = (int64_t{1} << 30) + static_cast<int64_t>((i * 7919 + j * 104729) % 65536) * 4096;
    table.Store(j, solved.data(), start.data(), SweepContraction{});
  }
  const uint32_t root_a = SurfaceRoot(bake, std::string(bake.mesh.surface_names[h.node_surface[table.source_node(0)]]));
  const uint32_t root_b = SurfaceRoot(bake, std::string(bake.mesh.surface_names[h.node_surface[table.source_node(1)]]));
  std::vector<int64_t> with_a(3 * size_t{n}, 0), with_b(3 * size_t{n}, 0), change(3 * size_t{n}, 0);
  table.AddTo(a.data(), root_a, with_a.data());
  table.AddTo(b.data(), root_b, with_b.data());
  table.AddChange(b.data(), root_b, a.data(), root_a, change.data());
  int64_t worst = 0;
  bool any = false;
  for (size_t i = 0; i < change.size(); ++i) {
    worst = std::max<int64_t>(worst, std::llabs(change[i] - (with_b[i] - with_a[i])));
    any = any || change[i] != 0;
  }
  EXPECT_TRUE(any);
  EXPECT_LE(worst, 1);  // each side rounded once
  std::vector<int64_t> same(3 * size_t{n}, 0);
  table.AddChange(a.data(), root_a, a.data(), root_a, same.data());
  EXPECT_TRUE(std::all_of(same.begin(), same.end(), [](int64_t v) { return v == 0; }));
}

}  // namespace
}  // namespace relight::testing
