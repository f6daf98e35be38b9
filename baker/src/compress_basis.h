// Clustered principal components of a luminaire's basis (Sloan et al. 2003,
// "Clustered principal components for precomputed radiance transfer"): the
// receivers are cut into clusters, each cluster's 3 x (N+1)^2 basis vectors
// are its mean plus r principal components, and weights and vectors are
// quantised into the runtime's form (bake.h BakeCompressedBasis). The
// cluster count and r are chosen per luminaire and receiver set: the
// smallest form whose error, measured at a set of looks (SH coefficient
// vectors of the luminaire at random aims), stays within a target.
//
// Clusters are runs of consecutive receivers in the mesher's order (a
// surface's vertices are consecutive, row by row), a multiple of 16 long so
// the run-time kernel's vector path covers them: cheaper than k-means on the
// term vectors and what lets the kernel read weights and write outputs in
// receiver order with no permutation.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/baker/baker.h"  // CompressionPoint

namespace relight::baker {

struct CompressionStats {
  bool compressed = false;  // false: the basis stays as it is (nothing smaller met the target)
  uint32_t clusters = 0, components = 0;
  // Over the looks, of each look's peak value of the luminaire's light on
  // these receivers (its SH part plus, when given, its direct light): the
  // largest and the mean absolute error of the compressed form.
  double max_error = 0, mean_error = 0;
  uint64_t bytes = 0;  // in memory: compressed, or the int16 basis when not compressed
  uint8_t weight_bits = 16;  // of the compressed form
};

// basis[c]: receivers x terms (per candela of Y_t, as luminance_basis.h);
// looks: SH coefficient vectors (terms each, candela) to measure the error
// at; direct: empty, or per look the luminaire's exact direct light on the
// receivers (receivers x 3), which counts towards each look's peak;
// max_error: the target, a fraction of each look's peak (> 0). Fills `out`
// when compressing pays; `curve`, if given, receives every candidate.
// try_8bit: every form is also weighed with a byte a weight, and an 8-bit
// form is kept when it is the smallest that meets max_error and a mean of
// max_error / 10 (BakeOptions::compress_8bit_weights).
CompressionStats CompressBasis(const std::array<Eigen::MatrixXd, 3>& basis,
                               const std::vector<Eigen::VectorXd>& looks,
                               const std::vector<Eigen::MatrixXd>& direct, double max_error,
                               int threads, BakeCompressedBasis* out,
                               std::vector<CompressionPoint>* curve = nullptr, bool try_8bit = false);

// The error of `cpca` as stored (quantised), at the looks, as in
// CompressionStats; threads as ParallelFor takes them (0: every core).
void MeasureCompressedError(const std::array<Eigen::MatrixXd, 3>& basis,
                            const BakeCompressedBasis& cpca, const std::vector<Eigen::VectorXd>& looks,
                            const std::vector<Eigen::MatrixXd>& direct, double* max_error,
                            double* mean_error, int threads = 1);

}  // namespace relight::baker
