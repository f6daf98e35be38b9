// The Baker: builds the shared core once, then bakes every luminaire's basis
// into the runtime's integer formats, or solves the exact reference.
#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "bake_hierarchy.h"
#include "grid_links.h"
#include "bake_lid.h"
#include "baker_core.h"
#include "compress_luminaire.h"
#include "luminaire_basis.h"
#include "parallel_for.h"
#include "quantise.h"
#include "reference.h"
#include "relight/baker/baker.h"
#include "relight/baker/photometry.h"
#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

// Display white when the scene names none: the 98th percentile of the
// vertex luminance at the default settings, so a few hot spots may clip.
constexpr double kWhitePercentile = 0.98;

void PutQ16_16(const Vec3& v, int32_t* out) {
  for (int a = 0; a < 3; ++a) out[a] = ToQ16_16(v[a]).raw();
}

void PutUnitQ1_14(const Vec3& v, std::vector<int16_t>* out) {
  for (int a = 0; a < 3; ++a) out->push_back(ToQ1_14(v[a]).raw());
}

BakeMesh MakeBakeMesh(const Scene& scene, const Mesh& mesh) {
  BakeMesh out;
  for (size_t v = 0; v < mesh.vertex_count(); ++v) {
    int32_t p[3];
    PutQ16_16(mesh.positions[v], p);
    out.positions.insert(out.positions.end(), p, p + 3);
    PutUnitQ1_14(mesh.vertex_normals[v], &out.normals);
    for (int c = 0; c < 3; ++c) out.albedo.push_back(ToAlbedo(mesh.vertex_reflectance[v][c]));
  }
  out.triangles = mesh.triangles;
  out.triangle_surface = mesh.triangle_surface;
  for (const Surface& s : scene.surfaces) out.surface_names.push_back(s.name);
  return out;
}

BakeGrid MakeBakeGrid(const CalcGrid& grid) {
  BakeGrid out;
  out.name = grid.name;
  out.columns = static_cast<uint32_t>(grid.columns);
  out.rows = static_cast<uint32_t>(grid.rows);
  for (size_t k = 0; k < grid.points.size(); ++k) {
    int32_t p[3];
    PutQ16_16(grid.points[k], p);
    out.points.insert(out.points.end(), p, p + 3);
    PutUnitQ1_14(grid.normals[k], &out.normals);
  }
  return out;
}

// Term-major basis[(t * count + r) * 3 + c], one scale per (term, channel).
BakeLightReceivers QuantiseReceivers(const ReceiverBasis& in, int threads) {
  BakeLightReceivers out;
  const size_t count = static_cast<size_t>(in.basis[0].rows());
  const size_t terms = static_cast<size_t>(in.basis[0].cols());
  out.basis.assign(terms * count * 3, 0);
  out.basis_scale.resize(terms * 3);
  ParallelFor(terms, threads, [&](size_t t, int) {  // a venue's basis is 10^7 values
    for (int c = 0; c < 3; ++c) {
      out.basis_scale[t * 3 + c] =
          QuantiseInt16(in.basis[c].col(static_cast<Eigen::Index>(t)).data(), count, 1,
                        &out.basis[t * count * 3 + c], 3);
    }
  });
  if (!in.direct.empty()) {
    std::vector<double> g;
    g.reserve(in.direct.size());
    for (const DirectGeometry& d : in.direct) {
      PutUnitQ1_14(d.direction, &out.direction);
      g.push_back(d.g_m2);
    }
    out.geometry.resize(g.size());
    out.geometry_scale = QuantiseUint32(g.data(), g.size(), out.geometry.data());
  }
  return out;
}

BakeLuminaire MakeBakeLuminaire(const Luminaire& lum, const LuminaireBasis& basis,
                                int lid_samples, int threads) {
  BakeLuminaire out;
  out.name = lum.name;
  PutQ16_16(lum.position, out.position);
  out.direct_mode =
      basis.mode == DirectModeKind::kExact ? DirectMode::kExactDirect : DirectMode::kAllInSh;
  out.sh_degree = static_cast<uint8_t>(basis.degree);
  out.use_sigma = lum.use_sigma.value_or(basis.mode == DirectModeKind::kAllInSh) ? 1 : 0;
  out.default_pan = ToQ16_16(lum.pan_deg).raw();
  out.default_tilt = ToQ16_16(lum.tilt_deg).raw();
  out.default_dimmer = ToLevelQ1_15(lum.dimmer).raw();
  for (int c = 0; c < 3; ++c) out.default_rgb[c] = ToLevelQ1_15(lum.colour[c]).raw();
  FillBakeLuminaireLid(lum, basis.degree, lid_samples, &out);  // mounting, frame, LID
  for (const ReceiverBasis& set : basis.sets) out.receivers.push_back(QuantiseReceivers(set, threads));
  return out;
}

BakeCamera MakeBakeCamera(const Camera& camera) {
  BakeCamera out;
  PutQ16_16(camera.position, out.position);
  PutQ16_16(camera.target, out.target);
  out.fov_y = ToQ16_16(camera.fov_y_deg).raw();
  return out;
}

double Photometric(const Rgb& rgb) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

}  // namespace

struct Baker::Impl {
  explicit Impl(bool show_progress) : progress(show_progress) {}
  Progress progress;
  std::unique_ptr<BakerCore> core;
  BakeReport report;
  // The hierarchy and links as the bake stores them, made as soon as the
  // solver is built so that the solver's own copy of the links can go
  // before the luminaires' solves (docs/venue.md, "Memory"); handed to the
  // one whole bake this Baker makes.
  std::optional<relight::BakeHierarchy> stored_hierarchy;
};

Baker::Baker(const Scene& scene, const BakeOptions& options)
    : impl_(std::make_unique<Impl>(options.progress)) {
  if (options.lid_samples < 2) {
    throw SceneError(scene.path, 0, "lid samples must be at least 2");
  }
  // No luminaire: no SH term to solve, and the solves would be handed empty
  // matrices. Only a hierarchy stored for run-time surface emitters is then
  // worth a bake. Checked before the form factors when the options decide it.
  const auto nothing_to_bake = [&] {
    throw SceneError(scene.path, 0,
                     "the scene has no luminaires: nothing to bake (add a [[luminaire]]; only a "
                     "hierarchical bake that stores its links for run-time surface emitters "
                     "needs none)");
  };
  if (scene.luminaires.empty() &&
      (!options.store_hierarchy || options.solver == SolverKind::kDense)) {
    nothing_to_bake();
  }
  Scene chosen = scene;
  const std::vector<LuminaireDegree> zoom_degrees =
      ChooseZoomDegrees(&chosen, options.direct_mode.value_or(DirectModeKind::kExact));
  impl_->core = BuildBakerCore(chosen, options, &impl_->progress);
  if (scene.luminaires.empty() && !impl_->core->hierarchical_solver) nothing_to_bake();
  if (HierarchicalSolver* solver = impl_->core->hierarchical_solver.get(); solver && options.store_hierarchy) {
    impl_->stored_hierarchy = MakeBakeHierarchy(impl_->core->mesh, solver->hierarchy(), solver->links());
    solver->ReleaseLinks();
  }
  impl_->report = impl_->core->report;
  impl_->report.zoom_degrees = zoom_degrees;
}

Baker::~Baker() = default;

relight::Bake Baker::Bake() {
  return BakePart([](size_t) { return true; }, true);
}

relight::Bake Baker::BakePart(const std::function<bool(size_t)>& mine, bool whole) {
  const Stopwatch total;
  const BakerCore& core = *impl_->core;
  if (whole && core.hierarchical_solver && core.options.store_hierarchy && !impl_->stored_hierarchy) {
    throw std::logic_error("relight-bake: a Baker stores its hierarchy in one whole bake only");
  }
  const Scene& scene = core.scene;
  relight::Bake bake;
  bake.scene_name = scene.name;
  bake.mesh = MakeBakeMesh(scene, core.mesh);
  for (const CalcGrid& g : scene.grids) bake.grids.push_back(MakeBakeGrid(g));
  bake.camera = MakeBakeCamera(scene.camera);

  const Stopwatch solve_time;
  size_t terms = 0;
  // Progress in SH terms: a solve's time grows with its terms.
  size_t all_terms = 0;
  for (size_t l = 0; l < scene.luminaires.size(); ++l)
    if (mine(l)) all_terms += static_cast<size_t>(ShTermCount(scene.luminaires[l].sh_degree));
  impl_->progress.Begin("basis luminances", all_terms);
  for (size_t l = 0; l < scene.luminaires.size(); ++l) {
    if (!mine(l)) continue;
    const LuminaireBasis basis = ComputeLuminaireBasis(core, l, EffectiveDirectMode(core));
    bake.luminaires.push_back(
        MakeBakeLuminaire(scene.luminaires[l], basis, core.options.lid_samples, core.options.threads));
    std::vector<ReceiverSetInput> sets(basis.sets.size());
    for (size_t s = 0; s < sets.size(); ++s) {
      sets[s].basis = &basis.sets[s].basis;
      for (const DirectGeometry& d : basis.sets[s].direct) {
        sets[s].direction.push_back(d.direction);
        sets[s].g_m2.push_back(d.g_m2);
      }
      if (s == 0) sets[s].rho = &core.mesh.vertex_reflectance;
    }
    const Stopwatch compress_time;
    CompressLuminaireBases(scene.luminaires[l], l, basis.degree, sets, core.options,
                           &bake.luminaires.back(), &impl_->report);
    impl_->report.compress_seconds += compress_time.seconds();
    terms += static_cast<size_t>(ShTermCount(basis.degree));
    impl_->progress.Advance(static_cast<size_t>(ShTermCount(basis.degree)));
  }
  impl_->progress.End();
  impl_->report.solve_seconds += solve_time.seconds();
  impl_->report.sh_terms = terms;

  double white = scene.white_cd_m2;
  // Without luminaires there is no light to set a white by (and the
  // reference would solve with zero right-hand sides): the default white.
  if (whole && !(white > 0) && !scene.luminaires.empty()) {
    const ReferenceResult ref = ComputeReference(core, DefaultSettings());
    std::vector<double> y;
    for (const Rgb& rgb : ref.vertex_luminance) y.push_back(Photometric(rgb));
    white = 0;
    if (!y.empty()) {
      const size_t rank =
          static_cast<size_t>(std::ceil(kWhitePercentile * static_cast<double>(y.size()))) - 1;
      std::nth_element(y.begin(), y.begin() + static_cast<std::ptrdiff_t>(rank), y.end());
      white = y[rank];
      if (!(white > 0)) white = *std::max_element(y.begin(), y.end());
    }
  }
  if (white > 0) bake.white_luminance = ToLightQ12(white).raw();
  // A white that rounds to 0 in LightQ12 keeps the format's default.
  if (bake.white_luminance <= 0) bake.white_luminance = relight::Bake().white_luminance;

  if (core.hierarchical_solver) {
    impl_->report.sweeps = core.hierarchical_solver->max_sweeps_used();
    impl_->report.residual = core.hierarchical_solver->max_residual();
    if (whole && core.options.store_hierarchy) {
      // Moved, not copied (0.9 GB on the 100k venue): a Baker makes one whole bake.
      bake.hierarchy = std::move(*impl_->stored_hierarchy);
      impl_->stored_hierarchy.reset();
      if (!core.gather.empty()) {
        const Stopwatch grid_time;
        MakeGridLinks(core.mesh, core.hierarchical_solver->hierarchy(), core.gather,
                      core.options.grid_link_epsilon, &*bake.hierarchy);
        impl_->report.grid_links = bake.hierarchy->grid_link_node.size();
        impl_->report.grid_link_seconds = grid_time.seconds();
      }
    }
  }
  impl_->report.total_seconds += total.seconds();
  return bake;
}

ReferenceResult Baker::Reference(const std::vector<FixtureSetting>& settings) {
  const Stopwatch time;
  ReferenceResult out = ComputeReference(*impl_->core, settings);
  if (impl_->core->hierarchical_solver) {
    impl_->report.sweeps = impl_->core->hierarchical_solver->max_sweeps_used();
    impl_->report.residual = impl_->core->hierarchical_solver->max_residual();
  }
  impl_->report.solve_seconds += time.seconds();
  impl_->report.total_seconds += time.seconds();
  return out;
}

std::vector<FixtureSetting> Baker::DefaultSettings() const {
  std::vector<FixtureSetting> out;
  for (const Luminaire& l : impl_->core->scene.luminaires) {
    out.push_back(FixtureSetting{l.pan_deg, l.tilt_deg, l.dimmer, l.colour});
  }
  return out;
}

const BakeReport& Baker::report() const { return impl_->report; }

const Scene& Baker::scene() const { return impl_->core->scene; }

}  // namespace relight::baker
