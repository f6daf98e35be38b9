// The principal components of every cluster of a luminaire's basis, for
// each cluster length the compression search weighs (compress_basis.cc):
// per cluster its mean, leading directions, weights, and the error at the
// search's looks for each number of components kept.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

namespace relight::baker {

// Cluster lengths tried (multiples of 16: the kernel's vector width) and the
// most components searched; the format allows more (kMaxCompressedComponents).
// Every length wins for some luminaire (the bytes against the length are not
// monotonic), so all are searched. Each is half the one before: a cluster is
// two of the next length (AllClusterPcas merges their moments).
inline constexpr uint32_t kClusterSizes[] = {2048, 1024, 512, 256, 128};
inline constexpr Eigen::Index kMaxSearchedComponents = 32;

struct ClusterPca {
  Eigen::Index start = 0, size = 0;
  Eigen::VectorXd mean;     // 3T
  Eigen::MatrixXd vectors;  // 3T x rc, unit principal directions, largest variance first
  Eigen::MatrixXd weights;  // size x rc
  // [r][look]: largest and summed |error| over the cluster with r components.
  Eigen::MatrixXd max_err, sum_err;
};

// Every cluster of every length in `sizes` (each a power-of-two fraction of
// kClusterSizes[0]) with at most caps[i] components, into
// pcas[size index][cluster]; x: receivers x 3T (the channels side by side),
// k: the looks (T x looks); threads as ParallelFor takes them.
void AllClusterPcas(const Eigen::MatrixXd& x, const Eigen::MatrixXd& k,
                    const std::vector<uint32_t>& sizes, const std::vector<Eigen::Index>& caps,
                    int threads, std::vector<std::vector<ClusterPca>>* pcas);

}  // namespace relight::baker
