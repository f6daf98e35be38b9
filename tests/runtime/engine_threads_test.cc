// Engine::Update on several threads (issue 13 "both cores"): the outputs
// after every step of a random sequence of changes are bit for bit those of
// one thread, on a baked floor with zooming beams and a grid, and on the
// synthetic bake with a (C, gamma) LID, an all-in-SH luminaire and grids.
// Also: the thread count is what was asked, and Update allocates nothing
// on the worker path either.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "bake_test_bake.h"
#include "count_allocations.h"
#include "relight/baker/baker.h"
#include "relight/baker/beam_profile.h"
#include "relight/engine/engine.h"

namespace relight {
namespace {

Bake BakedFloor() {
  baker::Scene s;
  s.name = "threads_floor";
  s.path = "engine_threads_test";
  s.patch_size_m = 0.4;
  baker::Surface floor;
  floor.name = "floor";
  floor.corners = {{-3, -3, 0}, {3, -3, 0}, {3, 3, 0}, {-3, 3, 0}};
  baker::Surface wall;
  wall.name = "wall";
  wall.corners = {{-3, 3, 0}, {3, 3, 0}, {3, 3, 2.5}, {-3, 3, 2.5}};
  s.surfaces = {floor, wall};
  for (int i = 0; i < 5; ++i) {
    baker::Luminaire lum;
    lum.name = "head" + std::to_string(i);
    lum.position = {-2.0 + i, -1.0 + 0.3 * i, 2.4};
    lum.sh_degree = 4;
    lum.sh_degree_given = true;
    if (i % 2 == 0) {
      lum.lid.kind = baker::LidKind::kBeam;
      lum.lid.beam_deg = 25;
      lum.lid.beam_exponent = baker::BeamProfileExponent(1.6);
      lum.lid.lumens = 2000;
      lum.lid.peak_cd = 2000 / baker::BeamLumensPerPeak(25, lum.lid.beam_exponent);
      lum.lid.zoom_min_deg = 10;
      lum.lid.zoom_max_deg = 50;
    } else {
      lum.lid.kind = baker::LidKind::kCosPower;
      lum.lid.exponent = 6;
      lum.lid.spread_deg = 90;
      lum.lid.peak_cd = 800;
    }
    s.luminaires.push_back(lum);
  }
  baker::CalcGrid grid;
  grid.name = "stage";
  for (int i = 0; i < 7; ++i) {
    grid.points.push_back({-1.5 + 0.5 * i, 0.2 * i, 0.01});
    grid.normals.push_back({0, 0, 1});
  }
  s.grids.push_back(grid);
  s.camera.position = {0, -4, 2};
  s.camera.target = {0, 0, 0};
  baker::BakeOptions options;
  options.threads = 2;
  options.lid_samples = 360;
  baker::Baker b(s, options);
  return b.Bake();
}

Q16_16 Deg(int d) { return Q16_16::FromInt(d); }

// One random change to engine `e` (the same draw applied to every engine).
struct Change {
  int kind, lum, a, b, c;
};

void Apply(Engine* e, const Change& ch) {
  switch (ch.kind) {
    case 0:
      (void)e->SetPanTilt(ch.lum, Deg(ch.a), Deg(ch.b));
      break;
    case 1:
      (void)e->SetDimmer(ch.lum, Q1_15::FromRaw(static_cast<int16_t>(ch.a)));
      break;
    case 2:
      (void)e->SetColour(ch.lum, Q1_15::FromRaw(static_cast<int16_t>(ch.a)),
                         Q1_15::FromRaw(static_cast<int16_t>(ch.b)), Q1_15::FromRaw(static_cast<int16_t>(ch.c)));
      break;
    case 3:
      (void)e->SetZoom(ch.lum, Deg(ch.a));  // kUnsupported without a zoom: no change
      break;
    default:
      (void)e->SetRoll(ch.lum, Deg(ch.a));
      break;
  }
}

// The engine's outputs (LuminanceView / IlluminanceView) as int32 pointers.
template <typename View>
const int32_t* Raw(const View& v) {
  return v.raw();
}

void ExpectSameOutputs(const Engine& one, const Engine& many, int step) {
  ASSERT_EQ(one.vertex_count(), many.vertex_count());
  ASSERT_EQ(0, std::memcmp(Raw(one.vertex_luminance()), Raw(many.vertex_luminance()),
                           static_cast<size_t>(one.vertex_count()) * 3 * sizeof(int32_t)))
      << "vertices differ at step " << step;
  for (int g = 0; g < static_cast<int>(one.bake().grids.size()); ++g) {
    const size_t n = static_cast<size_t>(one.bake().grids[g].point_count()) * 3 * sizeof(int32_t);
    ASSERT_EQ(0, std::memcmp(Raw(one.grid_illuminance(g)), Raw(many.grid_illuminance(g)), n)) << "grid " << g << " step " << step;
    ASSERT_EQ(0, std::memcmp(Raw(one.grid_direct_illuminance(g)), Raw(many.grid_direct_illuminance(g)), n))
        << "grid direct " << g << " step " << step;
  }
  EXPECT_EQ(one.last_update_luminaires_recombined(), many.last_update_luminaires_recombined());
  EXPECT_EQ(one.last_update_terms_recombined(), many.last_update_terms_recombined());
}

void RunSequence(const Bake& bake, int threads, uint32_t seed) {
  EngineOptions one_thread, several;
  one_thread.threads = 1;
  several.threads = threads;
  Engine one, many;
  ASSERT_TRUE(one.Open(bake, one_thread).ok());
  ASSERT_TRUE(many.Open(bake, several).ok());
  EXPECT_EQ(one.thread_count(), 1);
  EXPECT_EQ(many.thread_count(), threads);
  ExpectSameOutputs(one, many, -1);
  std::mt19937 rng(seed);
  const int lums = one.luminaire_count();
  std::uniform_int_distribution<int> kind(0, 4), lum(0, lums - 1), angle(-200, 200), level(-100, 32767),
      zoom(5, 60), count(1, 2 * lums);
  int recombined = 0;
  for (int step = 0; step < 60; ++step) {
    const int n = count(rng);
    for (int k = 0; k < n; ++k) {
      Change ch{kind(rng), lum(rng), 0, 0, 0};
      ch.a = ch.kind == 3 ? zoom(rng) : (ch.kind == 0 || ch.kind == 4 ? angle(rng) : level(rng));
      ch.b = ch.kind == 0 ? angle(rng) : level(rng);
      ch.c = level(rng);
      if (step % 7 == 3 && ch.kind == 1) ch.a = 0;  // some heads move in black
      Apply(&one, ch);
      Apply(&many, ch);
    }
    one.Update();
    many.Update();
    recombined += one.last_update_luminaires_recombined();
    ExpectSameOutputs(one, many, step);
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(recombined, 60);  // several luminaires rebuilt together, most steps
}

TEST(EngineThreads, BakedFloorBitIdenticalToOneThread) {
  const Bake bake = BakedFloor();
  ASSERT_GT(bake.mesh.vertex_count(), 200u);
  for (int threads : {2, 3}) RunSequence(bake, threads, 100 + threads);
}

TEST(EngineThreads, SyntheticBakeBitIdenticalToOneThread) {
  Bake bake = bake_test::MakeBake(17);
  // Two more exact-direct luminaires: axisymmetric, so the aimed direct term runs.
  std::mt19937 rng(5);
  for (const char* name : {"extra1", "extra2"}) {
    BakeLuminaire lum = bake_test::MakeLuminaire(&rng, name, DirectMode::kExactDirect, 2, 181);
    for (uint32_t s = 0; s < bake.receiver_set_count(); ++s) {
      lum.receivers.push_back(bake_test::MakeReceivers(&rng, lum, bake.receiver_count(s)));
    }
    bake.luminaires.push_back(lum);
  }
  for (int threads : {2, 4}) RunSequence(bake, threads, 200 + threads);
}

TEST(EngineThreads, UpdateOnWorkersAllocatesNothing) {
  const Bake bake = BakedFloor();
  EngineOptions options;
  options.threads = 2;
  Engine engine;
  ASSERT_TRUE(engine.Open(bake, options).ok());
  for (int i = 0; i < engine.luminaire_count(); ++i) (void)engine.SetPanTilt(i, Deg(10), Deg(20));
  engine.Update();  // warm
  g_allocations = 0;
  g_count_allocations = true;
  for (int step = 0; step < 20; ++step) {
    for (int i = 0; i < engine.luminaire_count(); ++i) {
      (void)engine.SetPanTilt(i, Deg(step), Deg(30 - step));
      (void)engine.SetZoom(i, Deg(12 + step));
    }
    engine.Update();
  }
  g_count_allocations = false;
  EXPECT_EQ(g_allocations.load(), 0);
}

TEST(EngineThreads, DefaultAndEnvironment) {
  const Bake bake = bake_test::MakeBake(3);
  Engine engine;
  ASSERT_TRUE(engine.Open(bake).ok());
  EXPECT_GE(engine.thread_count(), 1);
  EXPECT_LE(engine.thread_count(), 2);
  EngineOptions options;
  options.threads = 99;  // clamped
  ASSERT_TRUE(engine.Open(bake, options).ok());
  EXPECT_EQ(engine.thread_count(), 16);
}

}  // namespace
}  // namespace relight
