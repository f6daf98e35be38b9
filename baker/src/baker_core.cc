#include "baker_core.h"

#include <cmath>
#include <string>

#include "relight/sh_index.h"

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

}  // namespace

std::unique_ptr<BakerCore> BuildBakerCore(const Scene& scene, const BakeOptions& options,
                                          Progress* progress) {
  const Stopwatch total;
  ValidateForRadiosity(scene);
  auto core = std::make_unique<BakerCore>();
  core->scene = scene;
  core->options = options;
  core->mesh = BuildMesh(scene);
  const Mesh& mesh = core->mesh;
  core->visibility = std::make_unique<Visibility>(mesh, options.threads);
  core->samples = BuildPatchSampleSets(mesh);

  const Stopwatch ff_time;
  core->form_factors =
      ComputeFormFactors(mesh, *core->visibility, core->samples, options.threads, progress);
  for (const CalcGrid& g : scene.grids) {
    core->gather.push_back(ComputeGatherFactors(mesh, *core->visibility, core->samples, g.points,
                                                g.normals, options.threads, progress));
  }
  core->report.form_factor_seconds = ff_time.seconds();

  const Stopwatch solve_time;
  if (progress) progress->Begin("factorising", 1);
  std::vector<Rgb> rho;
  rho.reserve(mesh.patch_count());
  for (const Patch& p : mesh.patches) rho.push_back(p.reflectance);
  core->solver = std::make_unique<RadiositySolver>(core->form_factors, rho, options.threads);
  if (progress) {
    progress->Advance();
    progress->End();
  }
  core->report.solve_seconds = solve_time.seconds();

  if (progress) progress->Begin("direct light", scene.luminaires.size());
  for (const Luminaire& l : scene.luminaires) {
    core->direct.push_back(
        ComputeLuminaireDirect(mesh, *core->visibility, scene.grids, l.position, options.threads));
    if (progress) progress->Advance();
  }
  if (progress) progress->End();

  BakeReport& r = core->report;
  r.patches = mesh.patch_count();
  r.vertices = mesh.vertex_count();
  r.triangles = mesh.triangles.size() / 3;
  for (const CalcGrid& g : scene.grids) r.grid_points += g.points.size();
  r.luminaires = scene.luminaires.size();
  r.total_seconds = total.seconds();
  return core;
}

Eigen::MatrixXd AverageToVertices(const Mesh& mesh, const Eigen::MatrixXd& per_patch) {
  Eigen::MatrixXd out =
      Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(mesh.vertex_count()), per_patch.cols());
  for (size_t v = 0; v < mesh.vertex_count(); ++v) {
    double area = 0;
    for (uint32_t k = mesh.vertex_patch_offsets[v]; k < mesh.vertex_patch_offsets[v + 1]; ++k) {
      const uint32_t i = mesh.vertex_patch_ids[k];
      const double a = mesh.patches[i].area_m2;
      out.row(static_cast<Eigen::Index>(v)) += a * per_patch.row(static_cast<Eigen::Index>(i));
      area += a;
    }
    if (area > 0) out.row(static_cast<Eigen::Index>(v)) /= area;
  }
  return out;
}

}  // namespace relight::baker
