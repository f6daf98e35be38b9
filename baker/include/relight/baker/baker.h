// The baker's front door: a scene in, a bake (the runtime's format) out, and
// the float64 reference solve that every accuracy figure is measured against.
//
//   Baker baker(scene, options);          // mesh, Embree, form factors, factorise
//   relight::Bake bake = baker.Bake();    // every luminaire, every SH term, quantised
//   ReferenceResult ref = baker.Reference(settings);   // exact LIDs, no basis
//
// Both share the mesh and form factors, so a reference costs one extra solve.
// Input errors throw SceneError; the baker may use exceptions and the heap.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/baker/lid_error.h"
#include "relight/baker/scene.h"

namespace relight::baker {

// Radiosity solver. Dense: every patch pair's form factor and an LU
// factorisation per channel (exact, O(n^2) memory, O(n^3) time, at most
// 20000 patches). Hierarchical: Hanrahan et al.'s BF-refined links over a
// quadtree per surface and Gauss-Seidel sweeps (near-linear). Auto: dense
// up to kAutoDenseMaxPatches patches, hierarchical above.
enum class SolverKind { kAuto, kDense, kHierarchical };
constexpr size_t kAutoDenseMaxPatches = 4000;
// Hierarchical: where refinement starts. Off: from every pair of input
// surfaces (S²/2 pairs). On: from volume clusters above the surfaces
// (Smits, Arvo & Greenberg 1994; docs/venue.md), cost about n log n. Auto:
// on from kAutoClusterSurfaces input surfaces.
enum class ClusterMode { kAuto, kOn, kOff };
constexpr size_t kAutoClusterSurfaces = 2000;

class WorkShare;  // relight/baker/work_share.h
// relight-bake's --compress-error default (a fraction of peak; see
// BakeOptions::compress_error): measured to keep the stage and the Cornell
// box within 1 % max / 0.1 % mean of peak (docs/performance.md "Compressed bases").
inline constexpr double kDefaultCompressError = 0.01;

struct BakeOptions {
  std::optional<DirectModeKind> direct_mode;  // overrides every luminaire's mode when set
  int threads = 0;                            // 0 = all cores
  int lid_samples = 720;                      // M: gamma steps over 0..180 degrees (0.25 degree)
  bool progress = false;                      // draw a progress bar on stderr
  SolverKind solver = SolverKind::kAuto;
  // Hierarchical: a link is split while F times its source's estimated
  // exitance exceeds this fraction of the brightest exitance (BF refinement);
  // 0 links every pair of patches (the dense solver's form factors).
  double link_epsilon = 1e-3;
  // Hierarchical: bound each link's error also by link_epsilon times the
  // receiving surface's own peak illuminance, estimated by a first solve
  // over the links of the bound above, so dim surfaces are refined for
  // their own light (docs/hierarchy.md, "Receiver-relative refinement").
  bool receiver_relative_links = true;
  // Hierarchical: 256 visibility rays (not 16) for node pairs whose 16 rays disagree.
  bool adaptive_visibility = false;
  ClusterMode clusters = ClusterMode::kAuto;
  // Distributed bake: this process refines its share of the links and swaps
  // them with the others (relight/baker/work_share.h). Null: all of them here.
  const WorkShare* share = nullptr;
  // Hierarchical: sweeps stop when the residual |S + rho K M - M| of each
  // right-hand side is at most this x (1 - largest reflectance) of its peak
  // exitance, so the exitance's error is at most this fraction of the peak
  // (docs/hierarchy.md, "Solve").
  double solve_tolerance = 1e-4;
  // Hierarchical: store the quadtrees and links in the bake (sections HIER
  // and LINK) for light sources placed on surfaces at run time.
  bool store_hierarchy = true;
  // With the hierarchy stored and the scene's grids: links from nodes to
  // grid points (section GLNK), a node linked when the point sees its area
  // evenly to within this (sum over its leaves of |factor - even share|;
  // grid_links.h). Smaller: more, finer links.
  double grid_link_epsilon = 1e-4;
  // Clustered-PCA compression of the bases (compress_basis.h): the largest
  // error allowed, a fraction of the peak of each luminaire's own SH light
  // at random looks; 0 stores the bases uncompressed.
  double compress_error = 0;
  // Keep every candidate the compression weighs in BakeReport::compress_curve.
  // The search then fits every component count of every cluster length
  // instead of only those that could still give the smallest form (its
  // principal directions differ in rounding, so the form chosen can differ
  // by a few bytes).
  bool compress_curve = false;
  // A compressed basis keeps its weights in 8 bits instead of 16 (half the
  // bytes the run-time kernel streams) when, quantised so, its error at the
  // looks still meets compress_error (max) and a tenth of it (mean).
  bool compress_8bit_weights = true;
};

// One rate-error point of the basis compression: a cluster length and
// component count, its error (unquantised, fractions of peak as
// BakeOptions::compress_error) and its bytes in memory.
struct CompressionPoint {
  size_t luminaire = 0, set = 0;
  uint32_t cluster_size = 0, clusters = 0, components = 0;
  double max_error = 0, mean_error = 0;
  uint64_t bytes = 0;
};

struct BakeReport {
  size_t patches = 0, vertices = 0, triangles = 0, grid_points = 0;
  size_t luminaires = 0, sh_terms = 0;  // terms summed over luminaires
  double form_factor_seconds = 0, solve_seconds = 0, total_seconds = 0;
  double compress_seconds = 0;  // the part of solve_seconds spent compressing bases
  SolverKind solver = SolverKind::kDense;  // the one used (never kAuto)
  size_t nodes = 0, links = 0;             // hierarchical: quadtree nodes and links
  size_t clusters = 0, cluster_links = 0;  // hierarchical, clustered: volume clusters, their links
  size_t cluster_pairs_visited = 0;        // ... element pairs the refinement looked at
  size_t grid_links = 0;                   // stored hierarchy: node-to-grid-point links
  double grid_link_seconds = 0;            // ... and the time they took
  int sweeps = 0;                          // hierarchical: most Gauss-Seidel sweeps of a solve
  double residual = 0;  // hierarchical: largest residual a solve stopped at, of its peak exitance
  // Zooming beams without a scene sh_degree: the degree their narrowest angle got.
  std::vector<LuminaireDegree> zoom_degrees;
  // Bases in memory (compressed or int16) against the same values as float32,
  // and the compression's largest and mean error (fractions of peak, as
  // BakeOptions::compress_error) over the compressed ones.
  uint64_t basis_bytes = 0, basis_float32_bytes = 0;
  size_t bases_compressed = 0, bases = 0;
  size_t bases_8bit = 0;  // of the compressed ones, those with 8-bit weights
  double compress_max_error = 0, compress_mean_error = 0;
  // Every candidate the compression weighed (the docs' rate-error curve).
  std::vector<CompressionPoint> compress_curve;
};

// One fixture's state for a reference solve (same meaning as the runtime's).
struct FixtureSetting {
  double pan_deg = 0, tilt_deg = 0;
  double dimmer = 1;
  Rgb colour{1, 1, 1};
  std::optional<double> roll_deg{};  // about the beam axis; unset: the scene's roll
  std::optional<double> zoom_deg{};  // a zooming beam's full beam angle; unset: the scene's
};

struct ReferenceResult {
  // Per vertex RGB luminance, cd/m^2: exact direct at the vertex plus the
  // indirect averaged from adjacent patches (what the split mode approximates).
  std::vector<Rgb> vertex_luminance;
  // Per vertex RGB luminance, cd/m^2: total patch radiosity averaged from
  // adjacent patches (what Dobashi's all-in-SH mode approximates).
  std::vector<Rgb> vertex_luminance_patch_average;
  // Per grid, per point RGB illuminance in lux: total and direct only.
  std::vector<std::vector<Rgb>> grid_illuminance;
  std::vector<std::vector<Rgb>> grid_direct_illuminance;
};

class Baker {
 public:
  Baker(const Scene& scene, const BakeOptions& options);
  ~Baker();
  Baker(const Baker&) = delete;
  Baker& operator=(const Baker&) = delete;

  // Bases for every luminaire at its SH degree (a zooming beam without one:
  // the degree its narrowest angle needs, report().zoom_degrees), quantised
  // into the runtime's format.
  relight::Bake Bake();
  // Part of a bake split over processes (relight/baker/distributed.h): only
  // the luminaires `mine` accepts, in scene order; `whole` adds what the
  // writing process alone needs (the display white, the stored hierarchy).
  // Bake() is BakePart(every luminaire, true). A hierarchical bake that
  // stores its hierarchy (the default) hands the stored links over to its
  // one whole bake: a second whole bake from the same Baker throws
  // std::logic_error (the links were freed before the solves, for memory).
  relight::Bake BakePart(const std::function<bool(size_t)>& mine, bool whole);
  // The scene lit by the exact distributions at `settings` (one per luminaire,
  // in scene order), float64, no basis.
  ReferenceResult Reference(const std::vector<FixtureSetting>& settings);
  // Settings from the scene's defaults.
  std::vector<FixtureSetting> DefaultSettings() const;

  const BakeReport& report() const;
  // The scene as baked (zooming beams carry the SH degree chosen for them).
  const Scene& scene() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Compresses the bases of `bake`, an uncompressed bake of `scene` (its
// luminaires in the same order), as Baker::Bake would with
// options.compress_error, without solving radiosity again; fills the
// report's basis and compression fields. Throws SceneError when the two do
// not match, std::runtime_error when the bake is compressed already.
void RecompressBake(const Scene& scene, const BakeOptions& options, relight::Bake* bake,
                    BakeReport* report);

}  // namespace relight::baker
