// No heap after Open, counted over a long mixed run on a real hierarchical
// bake: after Engine::Open and the first Update, 10,000 updates of pan,
// tilt, 16-bit pan/tilt, dimmer, colour, roll and a surface emitter placed,
// moved, dimmed and removed (Engine::SetSurfaceEmitter) allocate nothing.
// Needs no baker: the bake is made on the host (relight-bake --solver
// hierarchical, see tests/runtime/cross_checks.cmake) and named by
// RELIGHT_TEST_HIER_BAKE (environment, else the build's default), so the
// same test runs natively and under qemu-aarch64.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <string>
#include <sys/stat.h>

#include "relight/engine/engine.h"
#include "relight/engine/surface_emitter.h"

#include "count_allocations.h"

namespace relight {
namespace {

std::string HierBakePath() {
  if (const char* env = std::getenv("RELIGHT_TEST_HIER_BAKE"); env != nullptr && env[0] != '\0') return env;
  return RELIGHT_TEST_HIER_BAKE;
}

bool FileExists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

Q16_16 Deg(int degrees) { return Q16_16::FromInt(degrees); }
Q1_15 Level(int per_mille) { return Q1_15::FromRaw(static_cast<int16_t>(per_mille * 32767 / 1000)); }
int32_t MetresQ16(int mm) { return static_cast<int32_t>(int64_t{mm} * 65536 / 1000); }

// A square emitter of `side_mm` on the living room's ceiling (room/+z,
// z = 2.7 m) centred at (x_mm, y_mm).
SurfaceEmitterShape CeilingSquare(int x_mm, int y_mm, int side_mm) {
  SurfaceEmitterShape shape;
  shape.surface = "room/+z";
  shape.corner_count = 4;
  const int h = side_mm / 2;
  const int xy[4][2] = {{x_mm - h, y_mm - h}, {x_mm + h, y_mm - h}, {x_mm + h, y_mm + h}, {x_mm - h, y_mm + h}};
  for (int k = 0; k < 4; ++k) {
    shape.corners_q16[k][0] = MetresQ16(xy[k][0]);
    shape.corners_q16[k][1] = MetresQ16(xy[k][1]);
    shape.corners_q16[k][2] = MetresQ16(2700);
  }
  return shape;
}

TEST(EngineNoAllocation, TenThousandMixedUpdatesOnAHierarchicalBake) {
  const std::string path = HierBakePath();
  if (!FileExists(path)) GTEST_SKIP() << "no hierarchical bake at '" << path << "' (set RELIGHT_TEST_HIER_BAKE)";
  Engine engine;
  // Without the later-bounce table (~2.5 s of Open here): the emitter tests
  // on the box check that placements with it allocate nothing.
  EngineOptions options;
  options.emitter_bounce_table_bytes = 0;
  const Status opened = engine.Open(path, options);
  ASSERT_TRUE(opened.ok()) << opened.ToString();
  ASSERT_GT(engine.luminaire_count(), 0);
  engine.Update();

  // The emitter's shape (its std::string included) is built before counting.
  SurfaceEmitterShape shape = CeilingSquare(3000, 2250, 400);
  const LightQ12 warm[3] = {LightQ12::FromRaw(300 << 12), LightQ12::FromRaw(220 << 12), LightQ12::FromRaw(150 << 12)};
  const LightQ12 dim[3] = {LightQ12::FromRaw(40 << 12), LightQ12::FromRaw(30 << 12), LightQ12::FromRaw(20 << 12)};
  ASSERT_TRUE(engine.SetSurfaceEmitter(0, shape, warm).ok()) << "the bake needs a hierarchy (--solver hierarchical)";
  engine.Update();

  g_allocations = 0;
  g_count_allocations = true;  // the counter works
  void* volatile probe = ::operator new(64);
  ::operator delete(probe);
  g_count_allocations = false;
  ASSERT_EQ(g_allocations.load(), 1);

  constexpr int kUpdates = 10000;
  const int luminaires = engine.luminaire_count();
  int failed = 0, recombined = 0, solved = 0;
  g_allocations = 0;
  g_count_allocations = true;
  for (int i = 0; i < kUpdates; ++i) {
    const int lum = i % luminaires;
    Status st;
    switch (i % 10) {
      case 0: st = engine.SetPanTilt(lum, Deg(i % 360 - 180), Deg(i % 120)); break;
      case 1: st = engine.SetPanTilt16(lum, static_cast<uint16_t>(i * 37), static_cast<uint16_t>(i * 91)); break;
      case 2: st = engine.SetDimmer(lum, Level(i % 1001)); break;
      case 3: st = engine.SetColour(lum, Level(i % 1000), Level(1000 - i % 1000), Level(500)); break;
      case 4: st = engine.SetRoll(lum, Deg(i % 360)); break;
      case 5: st = engine.SetSurfaceEmitterLuminance(0, (i / 10) % 2 ? dim : warm); break;
      case 6:  // move the emitter every 100 updates, across the ceiling
        if (i % 100 == 6) {
          const int step = i / 100;
          shape = CeilingSquare(1000 + (step * 97) % 4000, 800 + (step * 53) % 2900, 300 + (step % 5) * 100);
          st = engine.SetSurfaceEmitter(0, shape, warm);
        }
        break;
      case 7:  // a second emitter appears and goes
        if (i % 500 == 7) st = engine.SetSurfaceEmitter(1, CeilingSquare(1500, 1200, 500), dim);
        if (i % 500 == 257) st = engine.RemoveSurfaceEmitter(1);
        break;
      default: st = engine.SetDimmer(lum, Level((i * 7) % 1001)); break;
    }
    failed += st.ok() ? 0 : 1;
    engine.Update();
    recombined += engine.last_update_luminaires_recombined();
    solved += engine.last_update_emitters_solved();
  }
  g_count_allocations = false;
  EXPECT_EQ(failed, 0);
  EXPECT_GT(recombined, kUpdates / 10);
  EXPECT_GT(solved, kUpdates / 100);
  EXPECT_EQ(g_allocations.load(), 0) << "heap allocations after Open over " << kUpdates << " updates";
  std::printf("%d updates: %d luminaire caches rebuilt, %d emitter solves, %d allocations\n", kUpdates, recombined,
              solved, g_allocations.load());
}

}  // namespace
}  // namespace relight
