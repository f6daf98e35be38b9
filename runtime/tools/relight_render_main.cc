// relight-render: one bake + fixture settings -> PNG frame(s).
//
//   relight-render room.rlb --set spot1.pan=30 --set spot1.dimmer=0.8 -o frame.png
//   relight-render room.rlb --replay show.replay --fps 5 -o frames/frame_%04d.png
//   relight-render room.rlb --emitter "ceiling:2000:2.5,1.5,2.7;3.5,1.5,2.7;3.5,2.5,2.7" -o lit.png
//
// Reads top to bottom: open the bake, apply settings, update the engine, tone
// map, draw, write.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "relight/engine/engine.h"
#include "relight/render/osmesa_frame.h"
#include "relight/render/pick.h"
#include "frame_pipeline.h"
#include "emitter_args.h"
#include "replay_frames.h"
#include "replay_plan.h"
#include "set_args.h"

namespace {

int Fail(const std::string& message, int code) {
  std::fprintf(stderr, "relight-render: error: %s\n", message.c_str());
  return code;
}

bool ParseVec3(const std::string& text, float out[3]) {
  return std::sscanf(text.c_str(), "%f,%f,%f", &out[0], &out[1], &out[2]) == 3;
}

void PrintLuminaires(const relight::Engine& engine) {
  std::printf("luminaires in the bake (pan/tilt/roll in degrees, dimmer and colour 0..1):\n");
  for (int i = 0; i < engine.luminaire_count(); ++i) {
    const auto& lum = engine.bake().luminaires[i];
    const relight::FixtureState s = engine.state(i);
    std::printf("  %-20s pan %7.2f tilt %7.2f roll %7.2f dimmer %.3f colour %.3f,%.3f,%.3f  SH degree %d, %s\n",
                lum.name.c_str(), s.pan_deg.raw() / 65536.0, s.tilt_deg.raw() / 65536.0, s.roll_deg.raw() / 65536.0,
                s.dimmer.raw() / 32767.0, s.rgb[0].raw() / 32767.0, s.rgb[1].raw() / 32767.0,
                s.rgb[2].raw() / 32767.0, lum.sh_degree,
                lum.direct_mode == relight::DirectMode::kExactDirect ? "exact direct + SH indirect"
                                                                     : "all in SH");
  }
}

// Where --emitter can go: each surface's name, extent (metres) and facing,
// and whether the bake carries the hierarchy run-time emitters need.
void PrintSurfaces(const relight::Engine& engine) {
  const relight::BakeMesh& mesh = engine.bake().mesh;
  const size_t n = mesh.surface_names.size();
  std::vector<double> lo(3 * n, 1e300), hi(3 * n, -1e300), normal(3 * n, 0.0);
  for (uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    const size_t s = mesh.triangle_surface[t];
    if (s >= n) continue;
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.triangles[3 * size_t{t} + static_cast<size_t>(k)];
      for (int c = 0; c < 3; ++c) {
        const double x = mesh.positions[3 * size_t{v} + static_cast<size_t>(c)] / 65536.0;
        lo[3 * s + static_cast<size_t>(c)] = std::min(lo[3 * s + static_cast<size_t>(c)], x);
        hi[3 * s + static_cast<size_t>(c)] = std::max(hi[3 * s + static_cast<size_t>(c)], x);
        normal[3 * s + static_cast<size_t>(c)] += mesh.normals[3 * size_t{v} + static_cast<size_t>(c)];
      }
    }
  }
  std::printf("surfaces (extent x, y, z in metres; mean normal); --emitter %s:\n",
              engine.bake().hierarchy ? "places light sources on them"
                                      : "needs a bake of `relight-bake --solver hierarchical`");
  for (size_t s = 0; s < n; ++s) {
    if (lo[3 * s] > hi[3 * s]) continue;  // no triangles
    const double len = std::sqrt(normal[3 * s] * normal[3 * s] + normal[3 * s + 1] * normal[3 * s + 1] +
                                 normal[3 * s + 2] * normal[3 * s + 2]);
    std::printf("  %-20s x %6.2f..%-6.2f y %6.2f..%-6.2f z %6.2f..%-6.2f normal %5.2f,%5.2f,%5.2f\n",
                mesh.surface_names[s].c_str(), lo[3 * s], hi[3 * s], lo[3 * s + 1], hi[3 * s + 1], lo[3 * s + 2],
                hi[3 * s + 2], len > 0 ? normal[3 * s] / len : 0.0, len > 0 ? normal[3 * s + 1] / len : 0.0,
                len > 0 ? normal[3 * s + 2] / len : 0.0);
  }
}

// --aim-at-pixel: the point under pixel X,Y of the current view (ID pass and
// depth, Dobashi 4.2) becomes the luminaire's aim, as a console would do it.
int AimAtPixel(relight::Engine& engine, const relight::CameraView& view, int width, int height,
               const std::string& pixel, const std::string& luminaire) {
  int x = 0, y = 0;
  if (std::sscanf(pixel.c_str(), "%d,%d", &x, &y) != 2) return Fail("--aim-at-pixel wants X,Y", 2);
  const int index = luminaire.empty() ? 0 : engine.FindLuminaire(luminaire);
  if (index < 0 || index >= engine.luminaire_count()) {
    return Fail("--aim-luminaire: no luminaire '" + luminaire + "' in the bake (see --list)", 2);
  }
  relight::OsMesaFrame frame;
  if (relight::Status st = frame.Init(width, height, engine.bake().mesh); !st.ok()) return Fail(st.ToString(), 1);
  frame.SetCamera(view);
  relight::PickResult pick;
  if (relight::Status st = relight::PickPixel(&frame, engine.bake().mesh, x, y, &pick); !st.ok()) {
    return Fail("--aim-at-pixel " + pixel + ": " + st.ToString(), 2);
  }
  if (relight::Status st = engine.AimAt(index, pick.world_q16); !st.ok()) {
    return Fail("--aim-at-pixel " + pixel + ": cannot aim '" + engine.bake().luminaires[index].name +
                    "' there: " + st.ToString(), 2);
  }
  const relight::FixtureState s = engine.state(index);
  const auto& names = engine.bake().mesh.surface_names;
  std::printf("relight-render: aimed %s at %.3f,%.3f,%.3f (surface '%s'): pan %.2f tilt %.2f\n",
              engine.bake().luminaires[index].name.c_str(), pick.world_m[0], pick.world_m[1],
              pick.world_m[2], pick.surface < names.size() ? names[pick.surface].c_str() : "?",
              s.pan_deg.raw() / 65536.0, s.tilt_deg.raw() / 65536.0);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "relight-render: render a baked scene, relit by the given fixture settings, to PNG.\n"
      "Settings: --set FIXTURE.PARAM=VALUE with PARAM one of pan, tilt, roll (degrees, -720..720;\n"
      "roll turns the fixture about its beam axis), zoom (the full beam angle, degrees, within the\n"
      "bake's zoom range), dimmer (0..1 or 0..100%), r, g, b (0..1) or colour=R,G,B. Unset parameters keep the scene's defaults.\n"
      "Emitters: --emitter SURFACE:L:x,y,z;x,y,z;x,y,z[;...] puts a light source on a surface of a\n"
      "bake with a radiosity hierarchy (relight-bake --solver hierarchical): L its luminance in cd/m^2\n"
      "(or R,G,B), corners in metres around a convex polygon (3 to 8) on the surface's plane.\n"
      "Luminance (cd/m^2) is tone-mapped to sRGB with the bake's display white unless --white is given."};
  std::string bake_path, out_path = "frame.png", replay_path, camera_pos, camera_target, sheet_path;
  std::string aim_pixel, aim_luminaire;
  std::vector<std::string> sets, emitters;
  int width = 1280, height = 720;
  double fps = 5, white_cd_m2 = 0, fov = 0;
  bool list = false;
  app.add_option("bake", bake_path, "bake file written by relight-bake (.rlb)")->required();
  app.add_option("--set", sets, "fixture setting FIXTURE.PARAM=VALUE (repeatable)");
  app.add_option("--emitter", emitters,
                 "light source on a surface, SURFACE:L:x,y,z;x,y,z;x,y,z[;...] (L or R,G,B in cd/m^2, "
                 "corners in metres; repeatable, at most 8)");
  app.add_option("-o,--output", out_path,
                 "output PNG; with --replay a pattern with %d, e.g. frames/frame_%04d.png")
      ->capture_default_str();
  app.add_option("--width", width, "frame width in pixels")->capture_default_str()->check(CLI::Range(16, 8192));
  app.add_option("--height", height, "frame height in pixels")->capture_default_str()->check(CLI::Range(16, 8192));
  app.add_option("--camera-pos", camera_pos, "camera position X,Y,Z in metres (default: the scene's)");
  app.add_option("--camera-target", camera_target, "point looked at X,Y,Z in metres (default: the scene's)");
  app.add_option("--fov", fov, "vertical field of view, degrees (default: the scene's)")->check(CLI::Range(1.0, 170.0));
  app.add_option("--white", white_cd_m2, "luminance shown as display white, cd/m^2 (default: the bake's)")
      ->check(CLI::Range(0.001, 1e7));
  app.add_option("--replay", replay_path,
                 "replay script of timed settings ('TIME_S FIXTURE.PARAM=VALUE ...' per line): one frame per 1/fps seconds");
  app.add_option("--fps", fps, "frames per second of script time for --replay")->capture_default_str()->check(CLI::Range(relight::cli::kMinReplayFps, relight::cli::kMaxReplayFps));
  app.add_option("--sheet", sheet_path, "with --replay: also write all frames, half size, tiled 4 per row into this PNG");
  app.add_flag("--list", list, "print the bake's luminaires and their default settings, and its surfaces (for --emitter), then exit");
  app.add_option("--aim-at-pixel", aim_pixel,
                 "aim a luminaire at the surface point under pixel X,Y of the view (x right, y down)");
  app.add_option("--aim-luminaire", aim_luminaire, "the luminaire --aim-at-pixel moves (default: the first)");
  CLI11_PARSE(app, argc, argv);

  relight::Engine engine;
  relight::EngineOptions options;
  // A still image places each emitter once: solving it from the emission
  // costs less than the later-bounce table, which pays off when a replay
  // moves them.
  if (replay_path.empty()) options.emitter_bounce_table_bytes = 0;
  if (relight::Status st = engine.Open(bake_path, options); !st.ok()) return Fail(st.ToString(), 2);
  if (list) {
    PrintLuminaires(engine);
    PrintSurfaces(engine);
    return 0;
  }
  for (const std::string& text : sets) {
    std::string error;
    if (!relight::cli::ApplySetText(engine, text, &error)) {
      return Fail(error, 2);
    }
  }

  for (size_t i = 0; i < emitters.size(); ++i) {
    std::string error;
    if (!relight::cli::ApplyEmitterText(engine, static_cast<int>(i), emitters[i], &error)) {
      return Fail(error, 2);
    }
  }

  relight::CameraView view = relight::cli::CameraFromBake(engine.bake().camera);
  if (!camera_pos.empty() && !ParseVec3(camera_pos, view.position)) return Fail("--camera-pos wants X,Y,Z", 2);
  if (!camera_target.empty() && !ParseVec3(camera_target, view.target)) return Fail("--camera-target wants X,Y,Z", 2);
  if (fov > 0) view.fov_y_deg = static_cast<float>(fov);

  if (!aim_pixel.empty()) {
    if (int rc = AimAtPixel(engine, view, width, height, aim_pixel, aim_luminaire); rc != 0) return rc;
  }

  const int32_t white_q12 = white_cd_m2 > 0 ? static_cast<int32_t>(std::lround(white_cd_m2 * 4096.0)) : 0;
  relight::cli::FramePipeline pipeline;
  if (relight::Status st = pipeline.Init(engine, width, height, view, white_q12); !st.ok()) {
    return Fail(st.ToString(), 1);
  }
  const auto render_to = [&](const std::string& path) -> int {
    if (relight::Status st = pipeline.Render(engine); !st.ok()) return Fail(st.ToString(), 1);
    if (relight::Status st = relight::WritePngRgb8(path, pipeline.pixels(), width, height); !st.ok()) {
      return Fail(st.ToString(), 1);
    }
    return 0;
  };

  if (replay_path.empty()) {
    if (int rc = render_to(out_path); rc != 0) return rc;
    std::printf("relight-render: wrote %s (%dx%d)\n", out_path.c_str(), width, height);
    return 0;
  }
  return relight::cli::RenderReplay(engine, replay_path, fps, out_path, render_to,
                                    {sheet_path, pipeline.pixels(), width, height});
}
