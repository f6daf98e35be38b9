#include "reference.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "radiosity_vec.h"
#include "relight/baker/beam_profile.h"
#include "relight/baker/fixture_frame.h"
#include "relight/baker/photometry.h"

namespace relight::baker {
namespace {

using namespace radiosity_vec;

constexpr double kPi = 3.14159265358979323846;

// Illuminance (lux) of every luminaire at each point, one column per luminaire.
Eigen::MatrixXd PointIlluminance(const std::vector<const std::vector<DirectGeometry>*>& per_lum,
                                 const std::vector<const Lid*>& lids,
                                 const std::vector<FixtureFrame>& frames,
                                 size_t count) {
  Eigen::MatrixXd e = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(count),
                                            static_cast<Eigen::Index>(lids.size()));
  for (size_t l = 0; l < lids.size(); ++l) {
    for (size_t k = 0; k < count; ++k) {
      const DirectGeometry& d = (*per_lum[l])[k];
      if (d.g_m2 > 0) {
        e(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(l)) =
            d.g_m2 * ExactIntensity(*lids[l], frames[l], d.direction);
      }
    }
  }
  return e;
}

std::vector<Rgb> ToRgb(const std::array<Eigen::VectorXd, 3>& channels) {
  std::vector<Rgb> out(static_cast<size_t>(channels[0].size()));
  for (size_t k = 0; k < out.size(); ++k)
    for (int c = 0; c < 3; ++c) out[k][c] = channels[c](static_cast<Eigen::Index>(k));
  return out;
}

}  // namespace

double ExactIntensity(const Lid& lid, const Vec3& axis, const Vec3& dir) {
  const double cos_gamma = std::clamp(Dot(axis, dir), -1.0, 1.0);
  return lid.Evaluate(std::acos(cos_gamma) * (180.0 / kPi));
}

double ExactIntensity(const Lid& lid, const FixtureFrame& frame, const Vec3& dir) {
  if (lid.axisymmetric()) return ExactIntensity(lid, frame.axis, dir);
  return FrameIntensity(lid, frame, dir);
}

FixtureFrame SettingFrame(const Luminaire& lum, const FixtureSetting& setting) {
  return MakeFixtureFrame(FixturePose{lum.mounting, lum.yaw_deg, setting.pan_deg, setting.tilt_deg,
                                      setting.roll_deg.value_or(lum.roll_deg)});
}

ReferenceResult ComputeReference(const BakerCore& core,
                                 const std::vector<FixtureSetting>& settings) {
  const Scene& scene = core.scene;
  const Mesh& mesh = core.mesh;
  if (settings.size() != scene.luminaires.size()) {
    throw std::invalid_argument("reference: " + std::to_string(settings.size()) + " settings for " +
                                std::to_string(scene.luminaires.size()) + " luminaires");
  }
  const size_t lums = scene.luminaires.size();
  if (lums == 0) {  // Eigen would be handed n x 0 matrices
    throw SceneError(scene.path, 0, "the scene has no luminaires: no light to compute a reference for");
  }
  const auto n = static_cast<Eigen::Index>(mesh.patch_count());
  std::vector<FixtureFrame> frames;
  std::vector<const Lid*> lids;
  // Each LID as set: a zooming beam at the setting's angle (clamped to its
  // range as the engine clamps it), lumens held.
  std::vector<Lid> set_lids;
  set_lids.reserve(lums);
  for (size_t l = 0; l < lums; ++l) {
    const Lid& lid = scene.luminaires[l].lid;
    const std::optional<double>& zoom = settings[l].zoom_deg;
    if (zoom && !lid.zooms()) {  // a beam angle for a fixed beam would be dropped without a word
      throw SceneError(scene.path, scene.luminaires[l].line,
                       "reference: luminaire '" + scene.luminaires[l].name +
                           "' has no zoom (its LID is not a \"beam\" with a zoom range); its beam angle cannot be set");
    }
    set_lids.push_back(lid.zooms() && zoom ? ZoomedBeamLid(lid, std::clamp(*zoom, lid.zoom_min_deg,
                                                                           lid.zoom_max_deg))
                                           : lid);
  }
  Eigen::MatrixXd e(n, static_cast<Eigen::Index>(lums));
  for (size_t l = 0; l < lums; ++l) {
    const Luminaire& lum = scene.luminaires[l];
    frames.push_back(SettingFrame(lum, settings[l]));
    lids.push_back(&set_lids[l]);
    const FixtureFrame frame = frames.back();
    const Lid& lid = set_lids[l];
    e.col(static_cast<Eigen::Index>(l)) = PatchIlluminance(
        core.direct[l], [&](const Vec3& dir) { return ExactIntensity(lid, frame, dir); });
  }
  // Per channel, each luminaire's white-light result times dimmer x colour.
  std::array<Eigen::VectorXd, 3> level;
  for (int c = 0; c < 3; ++c) {
    level[c].resize(static_cast<Eigen::Index>(lums));
    for (size_t l = 0; l < lums; ++l)
      level[c](static_cast<Eigen::Index>(l)) = settings[l].dimmer * settings[l].colour[c];
  }

  std::vector<const std::vector<DirectGeometry>*> vertex_direct;
  for (size_t l = 0; l < lums; ++l) vertex_direct.push_back(&core.direct[l].vertices);
  const Eigen::MatrixXd e_vertex = PointIlluminance(vertex_direct, lids, frames, mesh.vertex_count());

  ReferenceResult out;
  std::array<Eigen::VectorXd, 3> split, patch_average;
  std::vector<std::array<Eigen::VectorXd, 3>> grid_total(scene.grids.size());
  std::vector<std::array<Eigen::VectorXd, 3>> grid_direct(scene.grids.size());
  std::vector<Eigen::MatrixXd> e_grid;
  for (size_t g = 0; g < scene.grids.size(); ++g) {
    std::vector<const std::vector<DirectGeometry>*> per_lum;
    for (size_t l = 0; l < lums; ++l) per_lum.push_back(&core.direct[l].grids[g]);
    e_grid.push_back(PointIlluminance(per_lum, lids, frames, scene.grids[g].points.size()));
  }
  const std::array<Eigen::MatrixXd, 3> m_rgb = SolveExitanceRgb(core, e);  // lm/m^2 per luminaire
  for (int c = 0; c < 3; ++c) {
    const Eigen::VectorXd& rho = Reflectance(core, c);
    const Eigen::MatrixXd& m = m_rgb[c];
    const Eigen::VectorXd m_sum = m * level[c];
    const Eigen::VectorXd indirect_patch = (m_sum - rho.asDiagonal() * (e * level[c])) / kPi;
    Eigen::VectorXd vertex_rho(static_cast<Eigen::Index>(mesh.vertex_count()));
    for (size_t v = 0; v < mesh.vertex_count(); ++v)
      vertex_rho(static_cast<Eigen::Index>(v)) = mesh.vertex_reflectance[v][c];
    // Exact direct at the vertex, reflected diffusely: L = rho E / pi.
    split[c] = vertex_rho.cwiseProduct(e_vertex * level[c]) / kPi +
               AverageToVertices(mesh, indirect_patch);
    patch_average[c] = AverageToVertices(mesh, m_sum / kPi);
    for (size_t g = 0; g < scene.grids.size(); ++g) {
      grid_direct[g][c] = e_grid[g] * level[c];
      grid_total[g][c] = grid_direct[g][c] + core.gather[g] * m_sum;
    }
  }
  out.vertex_luminance = ToRgb(split);
  out.vertex_luminance_patch_average = ToRgb(patch_average);
  for (size_t g = 0; g < scene.grids.size(); ++g) {
    out.grid_illuminance.push_back(ToRgb(grid_total[g]));
    out.grid_direct_illuminance.push_back(ToRgb(grid_direct[g]));
  }
  return out;
}

}  // namespace relight::baker
