// A luminaire's bases compressed into its BakeLuminaire (compress_basis.h)
// where that pays, with the bases' memory and the error counted into the
// report: shared by a fresh bake (basis_bake.cc) and the recompression of a
// written one (recompress.cc).
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/baker/baker.h"
#include "relight/baker/scene.h"

namespace relight::baker {

struct ReceiverSetInput {
  const std::array<Eigen::MatrixXd, 3>* basis = nullptr;  // receivers x terms per channel
  // The exact direct term's geometry per receiver (empty: the SH holds it all).
  std::vector<Vec3> direction;
  std::vector<double> g_m2;
  const std::vector<Rgb>* rho = nullptr;  // vertices: reflectance (luminance = rho E / pi)
};

// Compresses each set when options.compress_error > 0 (else only counts).
void CompressLuminaireBases(const Luminaire& lum, size_t index, int degree,
                            const std::vector<ReceiverSetInput>& sets, const BakeOptions& options,
                            BakeLuminaire* out, BakeReport* report);

}  // namespace relight::baker
