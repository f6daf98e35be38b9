// The frame's draw at a still camera: llvmpipe's rasterised colour pass (the
// culled one, as relightd draws from the second frame at a camera) against
// the still-camera resolve (render/src/pixel_resolve.h), on one bake's mesh
// and camera, with new vertex colours every frame. The ratio is the resolve
// over the rasterised draw, both measured in this run.
//   render_bench BAKE [--width W --height H] [Google Benchmark flags]
// Without BAKE (or RELIGHT_BENCH_BAKE) a 6 x 4 x 3 m room of ~50k triangles
// seen from inside stands in.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/render/osmesa_frame.h"

namespace {

using relight::BakeMesh;
using relight::CameraView;
using relight::OsMesaFrame;

struct Scene {
  BakeMesh mesh;
  CameraView view;
  std::string name;
};

int g_width = 1280, g_height = 720;
Scene* g_scene = nullptr;

void AddQuadGrid(BakeMesh* mesh, const double o[3], const double u[3], const double v[3], int nu, int nv) {
  const uint32_t base = mesh->vertex_count();
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      for (int a = 0; a < 3; ++a) {
        const double p = o[a] + u[a] * i / nu + v[a] * j / nv;
        mesh->positions.push_back(static_cast<int32_t>(std::lround(p * 65536.0)));
      }
    }
  }
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const uint32_t a = base + static_cast<uint32_t>(j * (nu + 1) + i), b = a + 1;
      const uint32_t c = a + static_cast<uint32_t>(nu + 1), d = c + 1;
      mesh->triangles.insert(mesh->triangles.end(), {a, b, d, a, d, c});
    }
  }
}

Scene StandInRoom() {
  Scene s;
  s.name = "stand-in room";
  const double faces[6][9] = {{0, 0, 0, 6, 0, 0, 0, 4, 0}, {0, 0, 3, 6, 0, 0, 0, 4, 0},
                              {0, 0, 0, 6, 0, 0, 0, 0, 3}, {0, 4, 0, 6, 0, 0, 0, 0, 3},
                              {0, 0, 0, 0, 4, 0, 0, 0, 3}, {6, 0, 0, 0, 4, 0, 0, 0, 3}};
  for (const auto& f : faces) {
    const int nu = static_cast<int>(std::lround(std::sqrt(f[3] * f[3] + f[4] * f[4] + f[5] * f[5]) / 0.0655));
    const int nv = static_cast<int>(std::lround(std::sqrt(f[6] * f[6] + f[7] * f[7] + f[8] * f[8]) / 0.0655));
    AddQuadGrid(&s.mesh, f, f + 3, f + 6, nu, nv);
  }
  const float eye[3] = {0.5f, 0.5f, 1.6f}, target[3] = {5, 3, 0.8f};
  std::memcpy(s.view.position, eye, sizeof(eye));
  std::memcpy(s.view.target, target, sizeof(target));
  s.view.fov_y_deg = 60;
  return s;
}

// A frame on the scene's mesh with random vertex colours and room for its pixels.
struct BenchFrame {
  OsMesaFrame frame;
  std::vector<uint8_t> rgb, pixels;

  bool Init(benchmark::State& state, bool resolve) {
    if (const relight::Status st = frame.Init(g_width, g_height, g_scene->mesh); !st.ok()) {
      state.SkipWithError(st.message().c_str());
      return false;
    }
    frame.SetStillCameraResolve(resolve);
    rgb.resize(static_cast<size_t>(g_scene->mesh.vertex_count()) * 3);
    pixels.resize(static_cast<size_t>(g_width) * g_height * 3);
    std::mt19937 rng(1);
    for (uint8_t& c : rgb) c = static_cast<uint8_t>(rng());
    return true;
  }
};

void DrawAtStillCamera(benchmark::State& state, bool resolve) {
  BenchFrame f;
  if (!f.Init(state, resolve)) return;
  auto& [frame, rgb, pixels] = f;
  frame.SetResolveThreads(static_cast<int>(state.range(0)));
  frame.SetCamera(g_scene->view);
  // The first draw at a camera, then the one that finds the shown triangles
  // (and, with the resolve, builds its table): relightd's first two frames.
  for (int i = 0; i < 2; ++i) (void)frame.Draw(rgb.data(), pixels.data());
  size_t frame_no = 0;
  for (auto _ : state) {
    rgb[frame_no++ % rgb.size()] ^= 0x5A;  // new colours every frame
    if (!frame.Draw(rgb.data(), pixels.data()).ok()) {
      state.SkipWithError("Draw failed");
      return;
    }
    benchmark::DoNotOptimize(pixels.data());
  }
  state.counters["resolved"] = frame.last_draw_resolved() ? 1 : 0;
  state.counters["triangles_shown"] = frame.last_drawn_triangles();
  state.counters["pixels"] = static_cast<double>(g_width) * g_height;
}

void BM_DrawRasterised(benchmark::State& state) { DrawAtStillCamera(state, false); }
void BM_DrawResolved(benchmark::State& state) { DrawAtStillCamera(state, true); }

// What a camera change costs: each iteration moves the camera 1 cm and draws
// Arg(0) frames there (1: a camera moving every frame; 2: one that stops).
// With the resolve the first draw is the ID pass, the table built from it
// and the resolve; without it, the full colour pass, then the ID pass and
// the culled colour pass.
void DrawsAtANewCamera(benchmark::State& state, bool resolve) {
  BenchFrame f;
  if (!f.Init(state, resolve)) return;
  auto& [frame, rgb, pixels] = f;
  CameraView view = g_scene->view;
  int step = 0;
  for (auto _ : state) {
    view.position[0] = g_scene->view.position[0] + 0.01f * static_cast<float>(step++ % 2);
    frame.SetCamera(view);
    for (int64_t i = 0; i < state.range(0); ++i) {
      if (!frame.Draw(rgb.data(), pixels.data()).ok()) {
        state.SkipWithError("Draw failed");
        return;
      }
    }
    benchmark::DoNotOptimize(pixels.data());
  }
  state.counters["resolved"] = frame.last_draw_resolved() ? 1 : 0;
}

void BM_NewCameraRasterised(benchmark::State& state) { DrawsAtANewCamera(state, false); }
void BM_NewCameraResolved(benchmark::State& state) { DrawsAtANewCamera(state, true); }

}  // namespace

// Arg: the resolve's threads (llvmpipe's are its own: LP_NUM_THREADS).
BENCHMARK(BM_DrawRasterised)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_DrawResolved)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_NewCameraRasterised)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_NewCameraResolved)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  std::string bake_path;
  if (const char* env = std::getenv("RELIGHT_BENCH_BAKE")) bake_path = env;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--width" || arg == "--height") && i + 1 < argc) {
      (arg == "--width" ? g_width : g_height) = std::atoi(argv[++i]);
    } else if (arg == "--help" || arg == "-h") {
      std::printf("usage: render_bench [BAKE] [--width W --height H] [Google Benchmark flags]\n"
                  "  draws at a still camera: llvmpipe's culled colour pass against the resolve.\n");
      return 0;
    } else {
      bake_path = arg;
    }
  }
  Scene scene;
  if (bake_path.empty()) {
    scene = StandInRoom();
  } else {
    relight::Bake bake;
    if (const relight::Status st = relight::ReadBake(bake_path, &bake); !st.ok()) {
      std::fprintf(stderr, "render_bench: %s\n", st.message().c_str());
      return 1;
    }
    scene.name = bake_path;
    scene.mesh = std::move(bake.mesh);
    for (int i = 0; i < 3; ++i) {
      scene.view.position[i] = static_cast<float>(bake.camera.position[i]) / 65536.0f;
      scene.view.target[i] = static_cast<float>(bake.camera.target[i]) / 65536.0f;
    }
    scene.view.fov_y_deg = static_cast<float>(bake.camera.fov_y) / 65536.0f;
  }
  g_scene = &scene;
  std::printf("render_bench: %s, %u vertices, %u triangles, %dx%d\n", scene.name.c_str(), scene.mesh.vertex_count(),
              scene.mesh.triangle_count(), g_width, g_height);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
