// relight-replay-hash: plays a replay script through the engine in script
// time (frame i shows the state at i / fps seconds; no clock, no renderer)
// and prints, per frame, a hash of the vertex luminances (LightQ12, before
// tone mapping) and of the tone-mapped 8-bit colours. The same bake and
// script must give the same hashes on every target and recombination path
// (x86-64 AVX2, x86-64 scalar with RELIGHT_FORCE_SCALAR=1, aarch64):
// scripts/cross-test.sh compares them.
//
//   relight-replay-hash living_room.rlb fixtures/living_room.replay --fps 2 [--dump DIR]
//
// stdout: "frame I t=SECONDS luminance=HASH rgb8=HASH" per frame, then a
// summary line; stderr: the engine's Update() time (mean, p50, p99, max over
// the frames), threads and CPU time, and the process's resident memory (for speed and
// footprints, not part of the comparison: the hashes do not depend on --threads).
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "emitter_args.h"
#include "relight/base/proc_status.h"
#include "relight/engine/engine.h"
#include "relight/engine/tone_map.h"
#include "relight/hal/replay_source.h"
#include "replay_hash.h"
#include "replay_plan.h"
#include "replay_step.h"
#include "relight/control/engine_binding.h"

namespace {

constexpr const char* kUsage =
    "usage: relight-replay-hash BAKE SCRIPT [--fps F] [--threads N] [--white CD_M2] [--emitter SPEC]... [--dump DIR]\n"
    "  --fps F         frames per second of script time (default 2)\n"
    "  --threads N     engine threads, 1..16 (default: RELIGHT_THREADS, else the cores, at most 2)\n"
    "  --white CD_M2   luminance shown as display white (default: the bake's)\n"
    "  --emitter SPEC  a surface emitter placed before the first frame, as relight-render's\n"
    "                  --emitter (SURFACE:L:x,y,z;x,y,z;x,y,z[;...]); repeatable\n"
    "  --dump DIR      also write DIR/frame_NNNN.luminance (int32 little-endian, 3 per vertex)\n"
    "                  and DIR/frame_NNNN.rgb8 (3 bytes per vertex)\n"
    "Set RELIGHT_FORCE_SCALAR=1 to keep the recombination off its vector paths, RELIGHT_SIMD=avx2 (or avxvnni,\n"
    "avx512vnni) to cap them at that level (the hashes are the same on every path).\n";

struct Args {
  std::string bake_path, script_path, dump_dir;
  double fps = 2, white_cd_m2 = 0;
  int threads = 0;
  std::vector<std::string> emitters;
};

bool ParseArgs(int argc, char** argv, Args* args) {
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "-h" || a == "--help") return false;
    if ((a == "--fps" || a == "--white") && has_value) {
      char* end = nullptr;
      const double v = std::strtod(argv[++i], &end);
      if (*end != '\0' || !std::isfinite(v) || v <= 0 || (a == "--fps" && v > 1000)) {
        std::fprintf(stderr, "relight-replay-hash: error: %s wants a positive number, got '%s'\n", a.c_str(), argv[i]);
        return false;
      }
      (a == "--fps" ? args->fps : args->white_cd_m2) = v;
    } else if (a == "--threads" && has_value) {
      char* end = nullptr;
      const long v = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || v < 1 || v > 16) {
        std::fprintf(stderr, "relight-replay-hash: error: --threads wants 1..16, got '%s'\n", argv[i]);
        return false;
      }
      args->threads = static_cast<int>(v);
    } else if (a == "--emitter" && has_value) {
      args->emitters.push_back(argv[++i]);
    } else if (a == "--dump" && has_value) {
      args->dump_dir = argv[++i];
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "relight-replay-hash: error: unknown option or missing value: %s\n", a.c_str());
      return false;
    } else {
      positional.push_back(a);
    }
  }
  if (positional.size() != 2) return false;
  args->bake_path = positional[0];
  args->script_path = positional[1];
  return true;
}

// CPU time of the whole process (every thread), microseconds: under load the
// wall clock measures the machine's share, this the engine's work.
// The calling thread's alone: with --threads 2 its share of the work, the
// critical path of Update() on an otherwise idle machine.
double CpuUs(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) / 1e3;
}

bool WriteFile(const std::string& path, const void* data, size_t size) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) {
    std::fprintf(stderr, "relight-replay-hash: error: cannot write %s: %s\n", path.c_str(), std::strerror(errno));
    return false;
  }
  const bool ok = std::fwrite(data, 1, size, f) == size;
  return std::fclose(f) == 0 && ok;
}

// Raw values of one frame; int32 as little-endian bytes whatever the host.
bool DumpFrame(const std::string& dir, int frame, const int32_t* luminance, const uint8_t* rgb8, uint32_t vertices) {
  std::vector<uint8_t> bytes(static_cast<size_t>(vertices) * 3 * 4);
  for (size_t i = 0; i < static_cast<size_t>(vertices) * 3; ++i) {
    const uint32_t v = static_cast<uint32_t>(luminance[i]);
    for (int b = 0; b < 4; ++b) bytes[i * 4 + static_cast<size_t>(b)] = static_cast<uint8_t>(v >> (8 * b));
  }
  char name[64];
  std::snprintf(name, sizeof name, "/frame_%04d", frame);
  return WriteFile(dir + name + ".luminance", bytes.data(), bytes.size()) &&
         WriteFile(dir + name + ".rgb8", rgb8, static_cast<size_t>(vertices) * 3);
}

}  // namespace

int main(int argc, char** argv) {
  Args args;
  if (!ParseArgs(argc, argv, &args)) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  relight::Engine engine;
  relight::EngineOptions options;
  options.threads = args.threads;
  if (relight::Status st = engine.Open(args.bake_path, options); !st.ok()) {
    std::fprintf(stderr, "relight-replay-hash: error: %s\n", st.ToString().c_str());
    return 1;
  }
  const long rss_after_open_kb = relight::ProcStatusKb("VmRSS");
  for (size_t i = 0; i < args.emitters.size(); ++i) {
    std::string error;
    if (!relight::cli::ApplyEmitterText(engine, static_cast<int>(i), args.emitters[i], &error)) {
      std::fprintf(stderr, "relight-replay-hash: error: %s\n", error.c_str());
      return 2;
    }
  }
  relight::hal::ReplaySource source(args.script_path, relight::control::LuminaireNames(engine));
  if (relight::Status st = source.Start(); !st.ok()) {
    std::fprintf(stderr, "relight-replay-hash: error: %s\n", st.ToString().c_str());
    return 2;
  }
  relight::ToneMap tone_map;
  const int32_t white_q12 = args.white_cd_m2 > 0 ? static_cast<int32_t>(std::lround(args.white_cd_m2 * 4096.0))
                                                 : engine.bake().white_luminance;
  relight::BuildToneMap(white_q12, &tone_map);

  const uint32_t vertices = engine.vertex_count();
  std::vector<uint8_t> rgb8(static_cast<size_t>(vertices) * 3);
  std::vector<relight::ParamChange> changes(256);
  relight::cli::ReplayPlan plan;
  if (std::string error; !relight::cli::PlanReplayFrames(source.duration_us(), args.fps, &plan, &error)) {
    std::fprintf(stderr, "relight-replay-hash: error: %s: %s\n", args.script_path.c_str(), error.c_str());
    return 2;
  }
  const int64_t frame_us = plan.frame_us;
  const int frames = static_cast<int>(plan.frames);  // <= kMaxReplayFrames
  uint64_t all_luminance = relight::cli::kFnv1a64Offset, all_rgb8 = relight::cli::kFnv1a64Offset;
  std::chrono::steady_clock::duration update_time{};
  std::vector<double> update_us(static_cast<size_t>(frames));
  double cpu_us = 0, main_cpu_us = 0;
  for (int i = 0; i < frames; ++i) {
    const int64_t now_us = static_cast<int64_t>(i) * frame_us;
    if (std::string error; !relight::cli::ApplyDueReplayChanges(source, args.script_path, now_us, engine, &changes,
                                                                 &error)) {
      std::fprintf(stderr, "relight-replay-hash: error: %s\n", error.c_str());
      return 2;
    }
    const double c0 = CpuUs(CLOCK_PROCESS_CPUTIME_ID), m0 = CpuUs(CLOCK_THREAD_CPUTIME_ID);
    const auto t0 = std::chrono::steady_clock::now();
    engine.Update();
    const auto took = std::chrono::steady_clock::now() - t0;
    cpu_us += CpuUs(CLOCK_PROCESS_CPUTIME_ID) - c0;
    main_cpu_us += CpuUs(CLOCK_THREAD_CPUTIME_ID) - m0;
    update_time += took;
    update_us[static_cast<size_t>(i)] = std::chrono::duration<double, std::micro>(took).count();
    const int32_t* luminance = engine.vertex_luminance().raw();
    relight::ToneMapRgb8(tone_map, engine.vertex_luminance(), rgb8.data());
    const uint64_t h_lum = relight::cli::HashInt32Le(luminance, uint64_t{vertices} * 3);
    const uint64_t h_rgb = relight::cli::HashBytes(rgb8.data(), rgb8.size());
    all_luminance = relight::cli::HashInt32Le(luminance, uint64_t{vertices} * 3, all_luminance);
    all_rgb8 = relight::cli::HashBytes(rgb8.data(), rgb8.size(), all_rgb8);
    std::printf("frame %d t=%.3f luminance=%016" PRIx64 " rgb8=%016" PRIx64 "\n", i,
                static_cast<double>(now_us) / 1e6, h_lum, h_rgb);
    if (!args.dump_dir.empty() && !DumpFrame(args.dump_dir, i, luminance, rgb8.data(), vertices)) return 1;
  }
  std::printf("frames %d vertices %u luminance=%016" PRIx64 " rgb8=%016" PRIx64 "\n", frames, vertices,
              all_luminance, all_rgb8);
  const double total_us = std::chrono::duration<double, std::micro>(update_time).count();
  // Nearest-rank percentiles over the frames.
  std::sort(update_us.begin(), update_us.end());
  const auto rank = [&](double p) {
    const size_t k = static_cast<size_t>(std::ceil(p / 100.0 * static_cast<double>(frames)));
    return update_us[k == 0 ? 0 : std::min(k, update_us.size()) - 1];
  };
  std::fprintf(stderr,
               "relight-replay-hash: engine Update() %.1f us/frame mean over %d frames (p50 %.1f, p99 %.1f, "
               "max %.1f us; %d threads; CPU %.1f us/frame, %.1f of it the calling thread's); RSS %ld kB after Open, "
               "%ld kB at the end, peak %ld kB\n",
               total_us / frames, frames, rank(50), rank(99), update_us.back(), engine.thread_count(), cpu_us / frames,
               main_cpu_us / frames,
               rss_after_open_kb, relight::ProcStatusKb("VmRSS"), relight::ProcStatusKb("VmHWM"));
  return 0;
}
