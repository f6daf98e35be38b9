// Run-time emitters on the calculation grids: the cost of the grid gather
// (EmitterGrids::OnSolved: every grid point sums f x B over its GLNK links,
// 3 channels) against one pan change and one emitter move, in one run:
//
//   BM_PanChange    Engine::Update() after a pan change (the baseline)
//   BM_EmitterMove  SetSurfaceEmitter to a new place + Update(): clip,
//                   solve, vertices, and the grid gather
//   BM_GridGather   the grid gather alone, from one node exitance
//
//   emitter_grid_bench BAKE.rlb SURFACE x0,y0,z0 x1,y1,z1 x2,y2,z2 [--benchmark_...]
//
// The bake needs a hierarchy with grid links (format version 6). The
// emitter is the triangle given, alternating with itself moved by 0.25 of
// its first edge. docs/hierarchy.md "Grids" has the figures and the command.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "emitter_grids.h"
#include "relight/engine/engine.h"

namespace {

relight::Engine* g_engine = nullptr;
relight::SurfaceEmitterShape g_shape[2];
relight::EmitterGrids* g_grids = nullptr;
std::vector<int64_t>* g_exitance = nullptr;

const relight::LightQ12 kWhite[3] = {relight::LightQ12::FromRaw(1000 << 12),
                                     relight::LightQ12::FromRaw(1000 << 12),
                                     relight::LightQ12::FromRaw(1000 << 12)};

void BM_PanChange(benchmark::State& state) {
  int i = 0;
  for (auto _ : state) {
    (void)g_engine->SetPanTilt(0, relight::Q16_16::FromInt(10 + (i++ & 1) * 20), relight::Q16_16::FromInt(30));
    g_engine->Update();
    benchmark::DoNotOptimize(g_engine->vertex_luminance());
  }
}

void BM_EmitterMove(benchmark::State& state) {
  int i = 0;
  for (auto _ : state) {
    (void)g_engine->SetSurfaceEmitter(0, g_shape[i++ & 1], kWhite);
    g_engine->Update();
    benchmark::DoNotOptimize(g_engine->grid_illuminance(0));
  }
}

void BM_GridGather(benchmark::State& state) {
  for (auto _ : state) {
    g_grids->OnSolved(0, g_exitance->data());
    benchmark::DoNotOptimize(g_grids->unit_q24(0));
  }
  const relight::BakeHierarchy& h = *g_engine->bake().hierarchy;
  state.counters["links"] = static_cast<double>(h.grid_link_node.size());
}

BENCHMARK(BM_PanChange)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmitterMove)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GridGather)->Unit(benchmark::kMillisecond);

bool ParseCorner(const char* text, double out[3]) {
  return std::sscanf(text, "%lf,%lf,%lf", &out[0], &out[1], &out[2]) == 3;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  double c[3][3];
  if (argc != 6 || !ParseCorner(argv[3], c[0]) || !ParseCorner(argv[4], c[1]) || !ParseCorner(argv[5], c[2])) {
    std::fprintf(stderr, "usage: emitter_grid_bench BAKE.rlb SURFACE x,y,z x,y,z x,y,z [--benchmark_...]\n");
    return 2;
  }
  relight::Engine engine;
  if (relight::Status st = engine.Open(argv[1]); !st.ok()) {
    std::fprintf(stderr, "%s\n", st.ToString().c_str());
    return 2;
  }
  const relight::Bake& bake = engine.bake();
  if (!bake.hierarchy || !bake.hierarchy->has_grid_links()) {
    std::fprintf(stderr, "%s: no grid links (bake it with relight-bake, format version 6)\n", argv[1]);
    return 2;
  }
  for (int s = 0; s < 2; ++s) {
    g_shape[s].surface = argv[2];
    g_shape[s].corner_count = 3;
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i)
        g_shape[s].corners_q16[k][i] =
            static_cast<int32_t>(std::lround((c[k][i] + 0.25 * s * (c[1][i] - c[0][i])) * 65536.0));
  }
  if (relight::Status st = engine.SetSurfaceEmitter(0, g_shape[1], kWhite); !st.ok()) {
    std::fprintf(stderr, "%s\n", st.ToString().c_str());
    return 2;
  }
  engine.Update();
  // Any exitance costs the same to gather: 1/8 lm/m^2 on every node.
  std::vector<int64_t> exitance(3 * size_t{bake.hierarchy->node_count()}, int64_t{1} << 29);
  relight::EmitterGrids grids;
  grids.Open(bake);
  g_engine = &engine;
  g_grids = &grids;
  g_exitance = &exitance;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
