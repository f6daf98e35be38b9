// relight-bake: scene (TOML + OBJ) -> bake file (.rlb), or the float64
// reference solve as CSV.
//
//   relight-bake fixtures/cornell_box.toml -o cornell.rlb
//   relight-bake fixtures/living_room.toml -o ref --reference --set spot1.pan=30
//
// Reads top to bottom: parse the command line, load the scene, build the
// baker (mesh, rays, form factors, factorisation), then bake and write or
// solve the reference and write CSV, then print a summary.
#include <sys/resource.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "relight/bake/bake.h"
#include "relight/baker/baker.h"
#include "relight/baker/distributed.h"
#include "relight/baker/lid_error.h"
#include "relight/baker/scene.h"
#include "mesher.h"
#include "reference_output.h"

namespace {

using relight::bake_cli::ApplySets;
using relight::bake_cli::GridsCsv;
using relight::bake_cli::VerticesCsv;
using relight::bake_cli::WriteFileAtomic;
using relight::baker::Baker;
using relight::baker::FixtureSetting;
using relight::baker::ReferenceResult;
using relight::baker::Rgb;
using relight::baker::Scene;

constexpr int kExitIo = 1;
constexpr int kExitBadInput = 2;

constexpr const char* kDescription =
    "relight-bake: bake the radiosity basis luminances of a scene (Dobashi et al.) into a\n"
    "bake file for the relight runtime, or solve the float64 reference.\n"
    "\n"
    "Units and conventions: metres, world z up, right-handed. Luminance in cd/m^2,\n"
    "illuminance in lux, intensity in candela. Pan turns about +z, counter-clockwise seen\n"
    "from above; tilt turns the beam from its rest axis (down when hanging, up when\n"
    "standing) towards +x of the panned frame; both in degrees. Dimmer and colour 0..1.\n"
    "Each luminaire gets (N+1)^2 SH terms for its sh_degree N. With --direct exact (the\n"
    "default) direct light is evaluated exactly at run time and the SH basis holds the\n"
    "indirect light; with --direct sh everything is in the SH basis (Dobashi's original).\n"
    "\n"
    "With --reference no bake is written: the scene is solved with the exact luminous\n"
    "intensity distributions at the scene's default settings (changed with --set) and\n"
    "OUT-vertices.csv (index,x_m,y_m,z_m,R,G,B in cd/m^2) and OUT-grids.csv\n"
    "(grid,point,x_m,y_m,z_m,E_total_lux,E_direct_lux, photometric Y = 0.2126 R +\n"
    "0.7152 G + 0.0722 B) are written (OUT without a trailing .csv or .rlb).\n"
    "\n"
    "Exit status: 0 on success, 2 for bad input (scene, luminaire file, arguments),\n"
    "1 when an output cannot be written. Outputs are written atomically: an existing\n"
    "file is never left half-written.";

struct Args {
  std::string scene_path;
  std::string out_path;
  std::string direct;  // empty: the scene's mode (exact)
  int threads = 0;
  std::string solver = "auto";
  std::string clusters = "auto";
  double patch_size_m = 0;  // 0: the scene's
  double link_epsilon = relight::baker::BakeOptions().link_epsilon;
  double grid_link_epsilon = relight::baker::BakeOptions().grid_link_epsilon;
  int lid_samples = 720;
  double lid_error_percent = 0;  // > 0: choose each luminaire's SH degree for this target
  bool quiet = false;
  bool reference = false;
  bool no_hierarchy = false;
  bool absolute_links = false;
  // Clustered-PCA compression of the bases: the largest error, percent of
  // each luminaire's own SH peak at random looks (docs/performance.md,
  // "Compressed bases"); 0 or --no-compress stores them uncompressed.
  double compress_error_percent = 100 * relight::baker::kDefaultCompressError;
  bool no_compress = false;
  bool weights_16bit = false;
  std::string compress_curve_path;  // CSV of every candidate weighed, for the docs' plot
  std::string recompress_path;      // an uncompressed bake of the scene to compress anew
  std::vector<std::string> sets;
};

int Fail(const std::string& message, int code) {
  std::fprintf(stderr, "relight-bake: error: %s\n", message.c_str());
  return code;
}

std::string OutputPrefix(std::string path) {
  for (const char* ext : {".csv", ".rlb"}) {
    const std::string e = ext;
    if (path.size() > e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0)
      return path.substr(0, path.size() - e.size());
  }
  return path;
}

double FileMegabytes(const std::string& path) {
  struct stat st {};
  return stat(path.c_str(), &st) == 0 ? static_cast<double>(st.st_size) / (1024.0 * 1024.0) : 0;
}

// Peak resident memory of this process so far, MB (Linux reports kB).
double PeakMegabytes() {
  struct rusage usage {};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// The stored hierarchy's share of the file: ", HIER 0.31 MB, LINK 9.80 MB" or "".
std::string HierarchySummary(const std::vector<relight::BakeSectionSize>& sections) {
  std::string out;
  for (const relight::BakeSectionSize& s : sections) {
    if (std::strcmp(s.tag, "HIER") != 0 && std::strcmp(s.tag, "LINK") != 0 &&
        std::strcmp(s.tag, "GLNK") != 0)
      continue;
    char text[64];
    std::snprintf(text, sizeof text, ", %s %.2f MB", s.tag,
                  static_cast<double>(s.stored_bytes) / (1024.0 * 1024.0));
    out += text;
  }
  return out;
}

std::string SolverSummary(const relight::baker::BakeReport& r) {
  if (r.solver != relight::baker::SolverKind::kHierarchical) return "dense solver";
  char text[200];
  std::snprintf(text, sizeof text,
                "hierarchical solver (%zu nodes, %zu links, %d sweeps, stopped at residual "
                "%.1e of peak)",
                r.nodes, r.links, r.sweeps, r.residual);
  std::string out = text;
  if (r.clusters > 0) {
    std::snprintf(text, sizeof text, ", %zu clusters with %zu cluster links", r.clusters,
                  r.cluster_links);
    out += text;
  }
  if (r.grid_links > 0) {
    std::snprintf(text, sizeof text, ", %zu grid links (%.2f per point, %.2f s)", r.grid_links,
                  static_cast<double>(r.grid_links) / static_cast<double>(r.grid_points),
                  r.grid_link_seconds);
    out += text;
  }
  return out;
}

void PrintSummary(const Scene& scene, const relight::baker::BakeReport& r,
                  const std::string& wrote) {
  for (const relight::baker::LuminaireDegree& d : r.zoom_degrees) {
    std::printf("relight-bake: %s: zoom: SH degree %d for its narrowest beam, %s LID error %.2f%% "
                "(window %s)%s\n",
                d.name.c_str(), d.choice.degree, relight::baker::LidErrorMeasureName(d.measure),
                100 * d.choice.error, relight::baker::ShWindowName(d.window),
                d.choice.met ? "" : ": the 2% target is not met even at the maximum degree");
  }
  std::printf(
      "relight-bake: %s: %zu patches, %zu vertices, %zu triangles, %zu grid points, "
      "%zu luminaire%s; %s; form factors %.2f s, solve %.2f s (compression %.2f s), total "
      "%.2f s, peak memory %.0f MB; %s\n",
      scene.name.c_str(), r.patches, r.vertices, r.triangles, r.grid_points, r.luminaires,
      r.luminaires == 1 ? "" : "s", SolverSummary(r).c_str(), r.form_factor_seconds,
      r.solve_seconds, r.compress_seconds, r.total_seconds, PeakMegabytes(), wrote.c_str());
}

// "relight-bake: bases: 21.4x vs float32, max 0.62 % / mean 0.04 % of peak (...)".
void PrintCompression(const relight::baker::BakeReport& r) {
  if (r.basis_bytes == 0) return;
  std::printf("relight-bake: bases: %.1fx vs float32 (%.2f MB in memory)",
              static_cast<double>(r.basis_float32_bytes) / static_cast<double>(r.basis_bytes),
              static_cast<double>(r.basis_bytes) / (1024.0 * 1024.0));
  if (r.bases_compressed > 0) {
    std::printf(", max %.2f %% / mean %.3f %% of peak (%zu of %zu bases compressed, %zu of them with 8-bit weights)",
                100 * r.compress_max_error, 100 * r.compress_mean_error, r.bases_compressed, r.bases,
                r.bases_8bit);
  } else {
    std::printf(", uncompressed");
  }
  std::printf("\n");
}

int Run(const Args& args, const relight::baker::DistributedSession& mpi) {
  if (!args.reference && !args.sets.empty()) {
    return Fail("--set applies to --reference only (a bake takes the scene's defaults)",
                kExitBadInput);
  }
  Scene scene = relight::baker::LoadScene(args.scene_path);
  if (args.patch_size_m > 0) scene.patch_size_m = args.patch_size_m;
  relight::baker::BakeOptions options;
  if (args.direct == "sh") options.direct_mode = relight::baker::DirectModeKind::kAllInSh;
  if (args.direct == "exact") options.direct_mode = relight::baker::DirectModeKind::kExact;
  options.threads = args.threads;
  if (args.solver == "dense") options.solver = relight::baker::SolverKind::kDense;
  if (args.solver == "hierarchical") options.solver = relight::baker::SolverKind::kHierarchical;
  if (args.clusters == "on") options.clusters = relight::baker::ClusterMode::kOn;
  if (args.clusters == "off") options.clusters = relight::baker::ClusterMode::kOff;
  options.link_epsilon = args.link_epsilon;
  options.receiver_relative_links = !args.absolute_links;
  options.grid_link_epsilon = args.grid_link_epsilon;
  options.store_hierarchy = !args.no_hierarchy;
  options.lid_samples = args.lid_samples;
  options.progress = !args.quiet && mpi.writer();
  // The links' refinement split over the ranks (a reference: rank 0 alone).
  options.share = args.reference ? nullptr : &mpi;
  // Ranks sharing a machine share its cores (docs/distributed-bake.md).
  if (options.threads == 0 && mpi.local_ranks() > 1) {
    options.threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()) /
                                      mpi.local_ranks());
  }
  options.compress_error = args.no_compress ? 0 : args.compress_error_percent / 100;
  options.compress_curve = !args.compress_curve_path.empty();
  options.compress_8bit_weights = !args.weights_16bit;
  if (args.lid_error_percent > 0) {
    const auto mode = options.direct_mode.value_or(relight::baker::DirectModeKind::kExact);
    for (const auto& d : relight::baker::ApplyLidErrorTarget(&scene, args.lid_error_percent / 100, mode)) {
      if (!mpi.writer()) continue;  // every rank sets the degrees; one says so
      std::printf("relight-bake: %s: SH degree %d (was %d), %s LID error %.2f%% (window %s)%s\n",
                  d.name.c_str(), d.choice.degree, d.old_degree,
                  relight::baker::LidErrorMeasureName(d.measure), 100 * d.choice.error,
                  relight::baker::ShWindowName(d.window),
                  d.choice.met ? "" : ": the target is not met even at the maximum degree");
    }
  }

  if (!args.reference) {
    relight::Bake bake;
    relight::baker::BakeReport report;
    {
      // The solver's form factors and links are freed before the file is
      // written: the stored hierarchy's encoding then takes their place.
      if (!args.recompress_path.empty()) {
        if (relight::Status st = relight::ReadBake(args.recompress_path, &bake); !st.ok()) {
          return Fail(args.recompress_path + ": " + st.ToString(), kExitBadInput);
        }
        relight::baker::RecompressBake(scene, options, &bake, &report);
      } else {
        Baker baker(scene, options);
        bake = relight::baker::DistributedBake(&baker, mpi, &report);
      }
    }
    if (!mpi.writer()) return 0;  // rank 0 writes the whole bake
    std::vector<relight::BakeSectionSize> sections;
    if (relight::Status st = relight::WriteBake(bake, args.out_path, &sections); !st.ok()) {
      return Fail(args.out_path + ": " + st.ToString(), kExitIo);
    }
    if (!args.compress_curve_path.empty()) {
      std::string csv = "luminaire,set,cluster_size,clusters,components,max_error,mean_error,bytes\n";
      for (const relight::baker::CompressionPoint& p : report.compress_curve) {
        char line[256];
        std::snprintf(line, sizeof line, "%zu,%zu,%u,%u,%u,%.9g,%.9g,%llu\n", p.luminaire, p.set,
                      p.cluster_size, p.clusters, p.components, p.max_error, p.mean_error,
                      static_cast<unsigned long long>(p.bytes));
        csv += line;
      }
      std::string error;
      if (!WriteFileAtomic(args.compress_curve_path, csv, &error)) return Fail(error, kExitIo);
    }
    char wrote[512];
    std::snprintf(wrote, sizeof wrote, "%zu SH terms; wrote %s (%.2f MB%s)", report.sh_terms,
                  args.out_path.c_str(), FileMegabytes(args.out_path),
                  HierarchySummary(sections).c_str());
    if (!args.quiet) {
      if (args.recompress_path.empty()) {
        PrintSummary(scene, report, wrote);
      } else {  // no mesh, solve or terms of its own to report
        std::printf("relight-bake: %s: recompressed %s; peak memory %.0f MB; %s\n", scene.name.c_str(),
                    args.recompress_path.c_str(), PeakMegabytes(), wrote);
      }
      PrintCompression(report);
      if (report.cluster_links > 0 && !args.no_hierarchy) {
        std::printf(
            "relight-bake: note: the stored hierarchy holds the %zu surface links, not the %zu "
            "cluster links: light sources placed on surfaces at run time miss the little light "
            "those carry (docs/venue.md)\n",
            report.links, report.cluster_links);
      }
    }
    return 0;
  }

  // A reference is one solve: rank 0 alone computes and writes it.
  if (!mpi.writer()) return 0;
  // Settings first: a typo in --set fails before minutes of form factors.
  std::vector<FixtureSetting> settings;
  for (const auto& l : scene.luminaires)
    settings.push_back(FixtureSetting{l.pan_deg, l.tilt_deg, l.dimmer, l.colour});
  std::string error;
  if (!ApplySets(scene, args.sets, &settings, &error)) return Fail(error, kExitBadInput);
  Baker baker(scene, options);
  const ReferenceResult ref = baker.Reference(settings);
  const std::string prefix = OutputPrefix(args.out_path);
  const std::string vertices_path = prefix + "-vertices.csv";
  const std::string grids_path = prefix + "-grids.csv";
  // The mesher is deterministic: this is the mesh the reference was solved on.
  const relight::baker::Mesh mesh =
      relight::baker::BuildMesh(scene, relight::baker::kMaxHierarchicalPatches);
  if (!WriteFileAtomic(vertices_path, VerticesCsv(mesh, ref), &error) ||
      !WriteFileAtomic(grids_path, GridsCsv(scene, ref), &error)) {
    return Fail(error, kExitIo);
  }
  if (!args.quiet) {
    char wrote[1024];
    std::snprintf(wrote, sizeof wrote,
                  "exact-distribution reference; wrote %s (%.2f MB) and %s (%.2f MB)",
                  vertices_path.c_str(), FileMegabytes(vertices_path), grids_path.c_str(),
                  FileMegabytes(grids_path));
    PrintSummary(scene, baker.report(), wrote);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{kDescription, "relight-bake"};
  Args args;
  app.add_option("scene", args.scene_path, "scene file (.toml)")->required();
  app.add_option("-o,--output", args.out_path,
                 "bake file to write (.rlb), or the CSV prefix with --reference")
      ->required();
  app.add_option("--direct", args.direct,
                 "exact (default): direct light exact at run time, SH holds the indirect; "
                 "sh: everything in SH (Dobashi's original)")
      ->check(CLI::IsMember({"exact", "sh"}));
  app.add_option("--solver", args.solver,
                 "radiosity solver: dense (every patch pair, LU; up to 20000 patches), "
                 "hierarchical (quadtrees and links, near-linear) or auto (dense up to 4000 "
                 "patches)")
      ->check(CLI::IsMember({"auto", "dense", "hierarchical"}))
      ->capture_default_str();
  app.add_option("--clusters", args.clusters,
                 "hierarchical: start the refinement from volume clusters above the surfaces "
                 "(on; cost about n log n in the input faces) or from every pair of surfaces "
                 "(off); auto: on from " +
                     std::to_string(relight::baker::kAutoClusterSurfaces) +
                     " input surfaces (docs/venue.md)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  app.add_option("--patch-size", args.patch_size_m,
                 "patch edge length in metres, instead of the scene's patch_size")
      ->check(CLI::PositiveNumber);
  app.add_option("--link-epsilon", args.link_epsilon,
                 "hierarchical: split a link while F x source exitance exceeds this fraction "
                 "of the brightest exitance (0 = every patch pair)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_flag("--absolute-links", args.absolute_links,
               "hierarchical: the absolute link bound alone, without the receiver-relative "
               "second refinement (fewer links; dim surfaces err more, docs/hierarchy.md)");
  app.add_option("--grid-link-epsilon", args.grid_link_epsilon,
                 "stored hierarchy: link a node to a grid point when the point sees its area "
                 "evenly to within this (docs/hierarchy.md \"Grids\"); smaller = more links")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app.add_option("--threads", args.threads, "worker threads (0 = all cores)")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  app.add_option("--lid-samples", args.lid_samples,
                 "M: the stored LID has M+1 samples over 0..180 degrees")
      ->check(CLI::Range(2, 1 << 20))
      ->capture_default_str();
  app.add_option("--lid-error", args.lid_error_percent,
                 "choose each luminaire's SH degree (instead of its sh_degree) as the smallest whose "
                 "series meets this LID error, percent: the flux misplaced at 10-degree resolution "
                 "(--direct exact) or the relative L2 error (--direct sh); docs/photometry.md")
      ->check(CLI::Range(0.001, 100.0));
  app.add_flag("--no-hierarchy", args.no_hierarchy,
               "hierarchical solver: leave its quadtrees and links out of the bake (a smaller "
               "file; only run-time light sources on surfaces need them)");
  app.add_option("--compress-error", args.compress_error_percent,
                 "compress each luminaire's basis (clustered PCA) to the smallest form whose error "
                 "stays within this percent of the peak of its own SH light at random looks; "
                 "0 stores the bases uncompressed")
      ->check(CLI::Range(0.0, 100.0))
      ->capture_default_str();
  app.add_option("--compress-curve", args.compress_curve_path,
                 "write every compression candidate weighed (cluster length, components, error, "
                 "bytes) to this CSV file; the search then weighs every component count of every "
                 "cluster length, which takes longer and can pick a form a few bytes apart");
  app.add_option("--recompress", args.recompress_path,
                 "compress the bases of this uncompressed bake of the scene (written by "
                 "--no-compress) instead of baking: no radiosity solve");
  app.add_flag("--no-compress", args.no_compress, "store the bases uncompressed (as --compress-error 0)");
  app.add_flag("--16bit-weights", args.weights_16bit,
               "keep every compressed basis's weights in 16 bits; by default a basis takes 8-bit "
               "weights (half the bytes the runtime reads a frame) when its error with them still "
               "meets --compress-error (max) and a tenth of it (mean)");
  app.add_flag("-q,--quiet", args.quiet, "no progress bar and no summary");
  app.add_flag("--reference", args.reference,
               "solve with the exact distributions and write CSV instead of a bake");
  app.add_option("--set", args.sets,
                 "with --reference: FIXTURE.PARAM=VALUE, PARAM one of pan, tilt, roll (degrees), "
                 "dimmer (0..1 or 0..100%), r, g, b (0..1), colour=R,G,B (repeatable)");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return Fail(e.what(), kExitBadInput);
  }
  relight::baker::DistributedSession mpi(&argc, &argv);
  if (mpi.idle()) return 0;
  // A failure on one rank ends them all, or the others would wait for it.
  const auto fail = [&mpi](const std::string& message, int code) {
    Fail(message, code);
    mpi.Abort(code);
    return code;
  };
  try {
    return Run(args, mpi);
  } catch (const relight::baker::SceneError& e) {
    return fail(e.what(), kExitBadInput);
  } catch (const std::bad_alloc&) {
    return fail("out of memory (raise patch_size to use fewer patches)", kExitIo);
  } catch (const std::exception& e) {
    return fail(e.what(), kExitIo);
  }
}
