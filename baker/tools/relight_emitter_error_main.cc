// relight-emitter-error: run-time emitters (the engine's FE solve on a
// hierarchical bake) against Chandran & Srivastava's naive method (the scene
// re-solved in float64 with the emitters as real emission: naive_emitter.h),
// per vertex, luminaires off. Prints the error in % of the naive peak.
// With --moved-by the engine's answer is a move's: each emitter is placed that
// far back from its polygon first, solved, then moved onto it.
//
//   relight-emitter-error fixtures/chandran_room.toml --emitter
//       "front_wall:2000:0.12,0,0.18;0.42,0,0.18;0.42,0,0.44;0.12,0,0.44"
//   relight-emitter-error fixtures/living_room.toml --patch-size 0.092 --bake lr16k.rlb --emitter ...
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "baker_core.h"
#include "emitter_args.h"
#include "naive_emitter.h"
#include "relight/bake/bake.h"
#include "relight/baker/baker.h"
#include "relight/baker/scene.h"
#include "relight/engine/engine.h"

namespace {

using Clock = std::chrono::steady_clock;

int Fail(const std::string& message) {
  std::fprintf(stderr, "relight-emitter-error: error: %s\n", message.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"run-time emitters (adaptive refine or fractional emissivity) against the naive float64 solve, per vertex"};
  std::string scene_path, bake_path, naive_solver = "auto", method = "ar";
  std::vector<std::string> emitters;
  double patch_size_m = 0, naive_epsilon = 2.5e-4, table_mb = 32;
  int refine_bits = relight::kDefaultSurfaceEmitterRefineBits;
  std::vector<double> moved_by;
  app.add_option("scene", scene_path, "scene TOML")->required();
  app.add_option("--emitter", emitters, "SURFACE:L:x,y,z;... (L cd/m^2 or R,G,B), up to 8")->required();
  app.add_option("--patch-size", patch_size_m, "patch edge length in metres, instead of the scene's");
  app.add_option("--bake", bake_path, "a hierarchical bake of the same scene and patch size (else baked here)");
  app.add_option("--naive-solver", naive_solver, "auto (dense up to 4000 patches), dense or hierarchical");
  app.add_option("--naive-link-epsilon", naive_epsilon, "link epsilon of a hierarchical naive solve");
  app.add_option("--method", method, "the engine's method: ar (adaptive refine, the engine's default) or fe (fractional emissivity)")
      ->check(CLI::IsMember({"ar", "fe"}));
  app.add_option("--bounce-table-mb", table_mb,
                 "memory for the engine's later-bounce table, MB (EngineOptions::emitter_bounce_table_bytes; 0: none)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--refine-bits", refine_bits,
                 "adaptive refine's threshold: new factors where a link carries 2^-N of the emitter's exitance "
                 "(EngineOptions::emitter_refine_bits)")
      ->check(CLI::Range(0, 32))
      ->capture_default_str();
  app.add_option("--moved-by", moved_by,
                 "DX,DY,DZ metres: measure a move, not a placement (each emitter is placed this far back from its "
                 "polygon and solved first, then moved onto it)")
      ->delimiter(',')
      ->expected(3);
  CLI11_PARSE(app, argc, argv);
  try {
    relight::baker::Scene scene = relight::baker::LoadScene(scene_path);
    if (patch_size_m > 0) scene.patch_size_m = patch_size_m;
    relight::Engine engine;
    relight::EngineOptions engine_options;
    engine_options.emitter_bounce_table_bytes = static_cast<int64_t>(table_mb * 1048576.0);
    engine_options.emitter_refine_bits = refine_bits;
    if (!bake_path.empty()) {
      if (relight::Status st = engine.Open(bake_path, engine_options); !st.ok()) return Fail(st.ToString());
    } else {
      relight::baker::BakeOptions options;
      options.solver = relight::baker::SolverKind::kHierarchical;
      if (relight::Status st = engine.Open(relight::baker::Baker(scene, options).Bake(), engine_options); !st.ok())
        return Fail(st.ToString());
    }
    for (int i = 0; i < engine.luminaire_count(); ++i) (void)engine.SetDimmer(i, relight::Q1_15::FromRaw(0));
    std::vector<relight::baker::NaiveEmitter> naive;
    for (size_t i = 0; i < emitters.size(); ++i) {
      relight::SurfaceEmitterShape shape;
      relight::LightQ12 light[3];
      std::string error;
      if (!relight::cli::ParseEmitterArg(emitters[i], &shape, light, &error))
        return Fail("--emitter '" + emitters[i] + "': " + error);
      shape.method = method == "fe" ? relight::SurfaceEmitterMethod::kFractionalEmissivity
                                    : relight::SurfaceEmitterMethod::kAdaptiveRefine;
      if (!moved_by.empty()) {  // where the move starts from, solved
        relight::SurfaceEmitterShape from = shape;
        for (int k = 0; k < from.corner_count; ++k)
          for (int a = 0; a < 3; ++a) from.corners_q16[k][a] -= static_cast<int32_t>(std::lround(moved_by[a] * 65536.0));
        if (relight::Status st = engine.SetSurfaceEmitter(static_cast<int>(i), from, light); !st.ok())
          return Fail("--emitter '" + emitters[i] + "' moved back by --moved-by: " + st.ToString());
        engine.Update();
      }
      if (relight::Status st = engine.SetSurfaceEmitter(static_cast<int>(i), shape, light); !st.ok())
        return Fail("--emitter '" + emitters[i] + "': " + st.ToString());
      relight::baker::NaiveEmitter e;  // the same polygon and luminance as the engine got
      e.surface = shape.surface;
      for (int k = 0; k < shape.corner_count; ++k)
        e.corners_m.push_back({shape.corners_q16[k][0] / 65536.0, shape.corners_q16[k][1] / 65536.0,
                               shape.corners_q16[k][2] / 65536.0});
      for (int c = 0; c < 3; ++c) e.luminance_cd_m2[c] = light[c].raw() / 4096.0;
      naive.push_back(e);
    }
    const auto t0 = Clock::now();
    engine.Update();
    const double fe_ms = 1e3 * std::chrono::duration<double>(Clock::now() - t0).count();

    relight::baker::BakeOptions options;
    options.solver = naive_solver == "dense"          ? relight::baker::SolverKind::kDense
                     : naive_solver == "hierarchical" ? relight::baker::SolverKind::kHierarchical
                                                      : relight::baker::SolverKind::kAuto;
    options.link_epsilon = naive_epsilon;
    options.solve_tolerance = 1e-7;
    const auto t1 = Clock::now();
    const auto core = relight::baker::BuildBakerCore(scene, options, nullptr);
    const Eigen::MatrixXd want = relight::baker::NaiveEmitterVertexLuminance(*core, naive);
    const double naive_s = std::chrono::duration<double>(Clock::now() - t1).count();
    if (static_cast<size_t>(want.rows()) != engine.bake().mesh.vertex_count())
      return Fail("the bake has " + std::to_string(engine.bake().mesh.vertex_count()) + " vertices, the scene meshes to " +
                  std::to_string(want.rows()) + ": not the same scene and patch size");
    const int32_t* got = engine.vertex_luminance().raw();
    std::printf("naive: %s solver, %zu patches, %.1f s; %s %s: %d sweeps, Update %.1f ms\n",
                core->solver ? "dense" : "hierarchical", core->mesh.patch_count(), naive_s, method == "fe" ? "FE" : "AR",
                moved_by.empty() ? "placement" : "move", engine.last_update_emitter_sweeps(), fe_ms);
    std::printf("channel | peak cd/m^2 | max error %% of peak | mean error %% of peak | vertices\n");
    for (int c = 0; c < 3; ++c) {
      const double peak = want.col(c).cwiseAbs().maxCoeff();
      double max_e = 0, sum_e = 0;
      for (Eigen::Index v = 0; v < want.rows(); ++v) {
        const double e = std::abs(got[3 * v + c] / 4096.0 - want(v, c));
        max_e = std::max(max_e, e);
        sum_e += e;
      }
      std::printf("%d | %.3f | %.3f | %.4f | %lld\n", c, peak, 100 * max_e / peak,
                  100 * sum_e / static_cast<double>(want.rows()) / peak, static_cast<long long>(want.rows()));
    }
  } catch (const std::exception& e) {
    return Fail(e.what());
  }
  return 0;
}
