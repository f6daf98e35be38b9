#include "baker_core.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include "cluster_links.h"
#include "cluster_tree.h"
#include "hierarchy.h"
#include "hierarchy_links.h"
#include "link_brightness.h"
#include "parallel_for.h"
#include "relight/base/sh_index.h"
#include "relight/baker/work_share.h"

namespace relight::baker {
namespace {

bool Finite(const Vec3& v) {
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

void ValidateForRadiosity(const Scene& scene) {
  for (const Surface& s : scene.surfaces) {
    for (double r : s.reflectance) {
      if (!(r >= 0 && r < 1)) {
        throw SceneError(scene.path, 0, "surface '" + s.name + "': reflectance must be in [0, 1)");
      }
    }
  }
  for (const Luminaire& l : scene.luminaires) {
    if (l.sh_degree < 0 || l.sh_degree > kMaxShDegree) {
      throw SceneError(scene.path, l.line,
                       "luminaire '" + l.name + "': sh_degree " + std::to_string(l.sh_degree) +
                           " is outside 0.." + std::to_string(kMaxShDegree));
    }
    if (!Finite(l.position)) {
      throw SceneError(scene.path, l.line, "luminaire '" + l.name + "': position is not finite");
    }
  }
  for (const CalcGrid& g : scene.grids) {
    if (g.points.size() != g.normals.size()) {
      throw SceneError(scene.path, 0, "grid '" + g.name + "': one normal per point expected");
    }
  }
}

void BuildDenseSolver(BakerCore* core, Progress* progress) {
  const Mesh& mesh = core->mesh;
  const Stopwatch ff_time;
  core->form_factors = ComputeFormFactors(mesh, *core->visibility, core->samples,
                                          core->options.threads, progress);
  core->report.form_factor_seconds += ff_time.seconds();
  const Stopwatch solve_time;
  if (progress) progress->Begin("factorising", 1);
  std::vector<Rgb> rho;
  rho.reserve(mesh.patch_count());
  for (const Patch& p : mesh.patches) rho.push_back(p.reflectance);
  core->solver = std::make_unique<RadiositySolver>(core->form_factors, rho, core->options.threads);
  if (progress) {
    progress->Advance();
    progress->End();
  }
  core->report.solve_seconds += solve_time.seconds();
}

// Every process's links, from each process's share of the root pairs
// (work_share.h), in the order RefineLinks gives them: sorted by (p, q).
std::vector<HierarchyLink> ShareLinks(const WorkShare& share,
                                      const std::vector<HierarchyLink>& mine) {
  static_assert(std::is_trivially_copyable_v<HierarchyLink>);
  std::vector<uint8_t> bytes(mine.size() * sizeof(HierarchyLink));
  if (!mine.empty()) std::memcpy(bytes.data(), mine.data(), bytes.size());
  const std::vector<uint8_t> all = share.AllGather(bytes);
  std::vector<HierarchyLink> links(all.size() / sizeof(HierarchyLink));
  if (!links.empty()) std::memcpy(links.data(), all.data(), links.size() * sizeof(HierarchyLink));
  std::sort(links.begin(), links.end(), [](const HierarchyLink& x, const HierarchyLink& y) {
    return x.p != y.p ? x.p < y.p : x.q < y.q;
  });
  return links;
}

// One refinement: from every pair of surfaces, or from the root cluster
// when `tree` has clusters (its surface pairs then refined as usual). The
// surface links are shared between ranks; every rank finds the same
// cluster links (the walk and its rays are deterministic).
struct RefinedLinks {
  std::vector<HierarchyLink> surface;
  std::vector<ClusterLink> cluster;
  size_t pairs_visited = 0;
};
RefinedLinks Refine(const BakerCore& core, const Hierarchy& h, const ClusterTree& tree,
                    const std::vector<double>& brightness, const std::vector<double>& epsilon,
                    Progress* progress) {
  const BakeOptions& o = core.options;
  const int rank = o.share ? o.share->rank() : 0, ranks = o.share ? o.share->ranks() : 1;
  RefinedLinks out;
  if (tree.empty()) {
    out.surface = RefineLinks(core.mesh, *core.visibility, core.samples, h, brightness, epsilon,
                              o.adaptive_visibility, o.threads, progress, rank, ranks);
  } else {
    const NodeSamples samples(h, core.samples);
    ClusteredRefinement c = RefineClusters(h, tree, samples, *core.visibility, brightness,
                                           epsilon, o.threads, progress);
    out.surface = RefineNodePairs(core.mesh, *core.visibility, core.samples, h, samples,
                                  std::move(c.node_pairs), brightness, epsilon,
                                  o.adaptive_visibility, o.threads, progress, rank, ranks);
    out.cluster = std::move(c.links);
    out.pairs_visited = c.pairs_visited;
  }
  if (ranks > 1) out.surface = ShareLinks(*o.share, out.surface);
  return out;
}

bool UseClusters(const BakeOptions& o, const Hierarchy& h) {
  switch (o.clusters) {
    case ClusterMode::kOn:
      return true;
    case ClusterMode::kOff:
      return false;
    case ClusterMode::kAuto:
      break;
  }
  return h.surface_count() >= kAutoClusterSurfaces;
}

void BuildHierarchicalSolver(BakerCore* core, Progress* progress) {
  const Mesh& mesh = core->mesh;
  const BakeOptions& o = core->options;
  if (!(o.link_epsilon >= 0) || !(o.solve_tolerance > 0)) {
    throw SceneError(core->scene.path, 0,
                     "hierarchical solver: link epsilon must be >= 0 and the tolerance > 0");
  }
  const Stopwatch ff_time;
  Hierarchy h = BuildHierarchy(mesh);
  ClusterTree tree = UseClusters(o, h) ? BuildClusterTree(h) : ClusterTree{};
  const std::vector<double> brightness =
      RefinementBrightness(core->scene, mesh, h, core->direct);
  // Relative to the area-weighted mean exitance (the roots' brightness):
  // the brightest patches (next to a luminaire) would make the scale useless.
  double area = 0, flux = 0;
  for (size_t s = 0; s < h.surface_count(); ++s) {
    const HierarchyNode& root = h.nodes[h.root(s)];
    area += root.area_m2;
    flux += root.area_m2 * brightness[h.root(s)];
  }
  const double epsilon = o.link_epsilon * flux / area;
  std::vector<Rgb> rho;
  rho.reserve(mesh.patch_count());
  for (const Patch& p : mesh.patches) rho.push_back(p.reflectance);
  HierarchicalSolveOptions solve;
  solve.tolerance = o.solve_tolerance;
  solve.threads = o.threads;
  RefinedLinks links =
      Refine(*core, h, tree, brightness, std::vector<double>(h.nodes.size(), epsilon), progress);
  // Receiver-relative: a first solve over these links, then every link again
  // against its receiver's own light (link_brightness.h). Every rank solves
  // the same links alike, so the shares still make one set.
  const std::vector<double> peak_direct = PeakDirectIlluminance(mesh, core->scene, core->direct);
  const bool lit = std::any_of(peak_direct.begin(), peak_direct.end(), [](double e) { return e > 0; });
  if (o.receiver_relative_links && lit && o.link_epsilon > 0) {
    const RefinementEstimate estimate = [&] {
      const HierarchicalSolver first(h, std::move(links.surface), rho, solve,
                                     ClusterSystem{tree, std::move(links.cluster)});
      return ReceiverRelativeEstimate(mesh, h, first, peak_direct, o.link_epsilon, epsilon);
    }();
    links = Refine(*core, h, tree, estimate.brightness, estimate.bound, progress);
  }
  core->report.nodes = h.nodes.size();
  core->report.links = links.surface.size();
  core->report.clusters = tree.clusters.size();
  core->report.cluster_links = links.cluster.size();
  core->report.cluster_pairs_visited = links.pairs_visited;
  core->report.form_factor_seconds += ff_time.seconds();
  core->hierarchical_solver = std::make_unique<HierarchicalSolver>(
      std::move(h), std::move(links.surface), rho, solve,
      ClusterSystem{std::move(tree), std::move(links.cluster)});
}

}  // namespace

std::unique_ptr<BakerCore> BuildBakerCore(const Scene& scene, const BakeOptions& options,
                                          Progress* progress) {
  const Stopwatch total;
  ValidateForRadiosity(scene);
  auto core = std::make_unique<BakerCore>();
  core->scene = scene;
  core->options = options;
  core->mesh = BuildMesh(scene, options.solver == SolverKind::kDense ? kMaxDensePatches
                                                                     : kMaxHierarchicalPatches);
  const Mesh& mesh = core->mesh;
  core->solver_kind = options.solver;
  if (core->solver_kind == SolverKind::kAuto) {
    core->solver_kind = mesh.patch_count() > kAutoDenseMaxPatches ? SolverKind::kHierarchical
                                                                   : SolverKind::kDense;
  }
  core->report.solver = core->solver_kind;
  core->visibility = std::make_unique<Visibility>(mesh, options.threads);
  core->samples = BuildPatchSampleSets(mesh);

  // Direct light first: the hierarchical solver refines its links by it.
  if (progress) progress->Begin("direct light", scene.luminaires.size());
  for (const Luminaire& l : scene.luminaires) {
    core->direct.push_back(
        ComputeLuminaireDirect(mesh, *core->visibility, scene.grids, l.position, options.threads));
    if (progress) progress->Advance();
  }
  if (progress) progress->End();

  if (core->solver_kind == SolverKind::kDense) {
    BuildDenseSolver(core.get(), progress);
  } else {
    BuildHierarchicalSolver(core.get(), progress);
  }
  const Stopwatch gather_time;
  for (const CalcGrid& g : scene.grids) {
    core->gather.push_back(ComputeGatherFactors(mesh, *core->visibility, core->samples, g.points,
                                                g.normals, options.threads, progress));
  }
  core->report.form_factor_seconds += gather_time.seconds();

  BakeReport& r = core->report;
  r.patches = mesh.patch_count();
  r.vertices = mesh.vertex_count();
  r.triangles = mesh.triangles.size() / 3;
  for (const CalcGrid& g : scene.grids) r.grid_points += g.points.size();
  r.luminaires = scene.luminaires.size();
  r.total_seconds = total.seconds();
  return core;
}

std::array<Eigen::MatrixXd, 3> SolveExitanceRgb(const BakerCore& core,
                                                const Eigen::MatrixXd& illuminance_lux) {
  if (core.hierarchical_solver) return core.hierarchical_solver->SolveExitanceRgb(illuminance_lux);
  std::array<Eigen::MatrixXd, 3> m;
  ParallelFor(3, std::min(2, ResolveThreads(core.options.threads)), [&](size_t c, int) {
    m[c] = core.solver->SolveExitance(static_cast<int>(c), illuminance_lux);
  });
  return m;
}

const Eigen::VectorXd& Reflectance(const BakerCore& core, int channel) {
  return core.hierarchical_solver ? core.hierarchical_solver->reflectance(channel)
                                  : core.solver->reflectance(channel);
}

Eigen::MatrixXd AverageToVertices(const Mesh& mesh, const Eigen::MatrixXd& per_patch, int threads) {
  const Eigen::Index vertices = static_cast<Eigen::Index>(mesh.vertex_count());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(vertices, per_patch.cols());
  std::vector<double> area(mesh.vertex_count(), 0.0);
  for (size_t v = 0; v < mesh.vertex_count(); ++v) {
    for (uint32_t k = mesh.vertex_patch_offsets[v]; k < mesh.vertex_patch_offsets[v + 1]; ++k)
      area[v] += mesh.patches[mesh.vertex_patch_ids[k]].area_m2;
  }
  // Column by column (the matrices are column-major), columns in parallel;
  // each value is summed over its patches in the same order as ever.
  ParallelFor(static_cast<size_t>(per_patch.cols()), threads, [&](size_t j, int) {
    const double* in = per_patch.col(static_cast<Eigen::Index>(j)).data();
    double* col = out.col(static_cast<Eigen::Index>(j)).data();
    for (size_t v = 0; v < mesh.vertex_count(); ++v) {
      double sum = 0;
      for (uint32_t k = mesh.vertex_patch_offsets[v]; k < mesh.vertex_patch_offsets[v + 1]; ++k) {
        const uint32_t i = mesh.vertex_patch_ids[k];
        sum += mesh.patches[i].area_m2 * in[i];
      }
      col[v] = area[v] > 0 ? sum / area[v] : sum;
    }
  });
  return out;
}

}  // namespace relight::baker
