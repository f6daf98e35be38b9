// RecompressBake (baker.h): the bases of a written bake compressed anew,
// without solving radiosity again. The int16 bases are the values the
// engine would recombine, so the error is measured against exactly them.
#include <stdexcept>
#include <string>

#include "compress_luminaire.h"
#include "quantise.h"
#include "relight/baker/baker.h"
#include "relight/base/sh_index.h"

namespace relight::baker {
namespace {

std::array<Eigen::MatrixXd, 3> Dequantise(const BakeLightReceivers& rec, int terms, uint32_t count) {
  std::array<Eigen::MatrixXd, 3> out;
  for (int c = 0; c < 3; ++c) {
    out[static_cast<size_t>(c)].resize(count, terms);
    for (int t = 0; t < terms; ++t) {
      const double s = QuantScaleValue(rec.basis_scale[static_cast<size_t>(t * 3 + c)]);
      for (uint32_t r = 0; r < count; ++r) {
        out[static_cast<size_t>(c)](r, t) = s * rec.basis[(static_cast<size_t>(t) * count + r) * 3 + static_cast<size_t>(c)];
      }
    }
  }
  return out;
}

}  // namespace

void RecompressBake(const Scene& scene, const BakeOptions& options, relight::Bake* bake, BakeReport* report) {
  if (scene.luminaires.size() != bake->luminaires.size()) {
    throw SceneError(scene.path, 0, "--recompress: the scene has " + std::to_string(scene.luminaires.size()) +
                                        " luminaires, the bake " + std::to_string(bake->luminaires.size()));
  }
  std::vector<Rgb> rho(bake->mesh.vertex_count());
  for (size_t v = 0; v < rho.size(); ++v) {
    for (size_t c = 0; c < 3; ++c) rho[v][c] = bake->mesh.albedo[v * 3 + c] / 65535.0;
  }
  for (size_t l = 0; l < bake->luminaires.size(); ++l) {
    BakeLuminaire& lum = bake->luminaires[l];
    const Luminaire& src = scene.luminaires[l];
    if (src.name != lum.name) {
      throw SceneError(scene.path, src.line, "--recompress: luminaire " + std::to_string(l) + " is '" +
                                                 src.name + "' in the scene, '" + lum.name + "' in the bake");
    }
    const int terms = ShTermCount(lum.sh_degree);
    report->sh_terms += static_cast<size_t>(terms);
    std::vector<std::array<Eigen::MatrixXd, 3>> bases;
    std::vector<ReceiverSetInput> sets(lum.receivers.size());
    bases.reserve(sets.size());
    for (size_t s = 0; s < sets.size(); ++s) {
      const BakeLightReceivers& rec = lum.receivers[s];
      if (rec.compressed.present()) throw std::runtime_error("--recompress: the bake is compressed already");
      const uint32_t count = bake->receiver_count(static_cast<uint32_t>(s));
      bases.push_back(Dequantise(rec, terms, count));
      sets[s].basis = &bases.back();
      const double g_scale = QuantScaleValue(rec.geometry_scale);
      for (size_t r = 0; r < rec.geometry.size(); ++r) {
        sets[s].direction.push_back(Vec3{rec.direction[3 * r] / 16384.0, rec.direction[3 * r + 1] / 16384.0,
                                         rec.direction[3 * r + 2] / 16384.0});
        sets[s].g_m2.push_back(rec.geometry[r] * g_scale);
      }
      if (s == 0) sets[s].rho = &rho;
    }
    CompressLuminaireBases(src, l, lum.sh_degree, sets, options, &lum, report);
  }
}

}  // namespace relight::baker
