// Clustered PCA of a basis (see compress_basis.h). Sloan et al. 2003.
#include "compress_basis.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cluster_pca.h"
#include "dense_blas.h"
#include "parallel_for.h"
#include "quantise.h"

namespace relight::baker {
namespace {

// Unquantised candidates must meet this share of the target: quantising the
// weights and vectors adds a little error of its own.
constexpr double kQuantisationHeadroom = 0.8;

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// Receivers x (3 terms): channel c in columns [c T, (c + 1) T).
MatrixXd StackChannels(const std::array<MatrixXd, 3>& basis) {
  const Index n = basis[0].rows(), t = basis[0].cols();
  MatrixXd x(n, 3 * t);
  for (int c = 0; c < 3; ++c) x.middleCols(c * t, t) = basis[c];
  return x;
}

MatrixXd LookMatrix(const std::vector<VectorXd>& looks, Index terms) {
  MatrixXd k(terms, static_cast<Index>(looks.size()));
  for (size_t l = 0; l < looks.size(); ++l) k.col(static_cast<Index>(l)) = looks[l];
  return k;
}

// Receivers a task takes in the passes over all receivers.
constexpr Index kRowChunk = 4096;

// Per look, the largest |value| of the uncompressed basis plus the direct
// light (if given) over receivers and channels.
VectorXd LookPeaks(const MatrixXd& x, const MatrixXd& k, const std::vector<MatrixXd>& direct,
                   int threads) {
  const Index t = k.rows(), rows = x.rows();
  const size_t chunks = static_cast<size_t>((rows + kRowChunk - 1) / kRowChunk);
  std::vector<VectorXd> chunk_peak(chunks, VectorXd::Zero(k.cols()));
  ParallelFor(chunks, threads, [&](size_t ch, int) {
    const Index from = static_cast<Index>(ch) * kRowChunk, n = std::min(kRowChunk, rows - from);
    for (int c = 0; c < 3; ++c) {
      MatrixXd v = Multiply(x.block(from, c * t, n, t), k);
      for (size_t l = 0; l < direct.size(); ++l)
        v.col(static_cast<Index>(l)) += direct[l].block(from, c, n, 1);
      chunk_peak[ch] = chunk_peak[ch].cwiseMax(v.cwiseAbs().colwise().maxCoeff().transpose());
    }
  });
  VectorXd peak = VectorXd::Zero(k.cols());
  for (const VectorXd& p : chunk_peak) peak = peak.cwiseMax(p);
  return peak;
}


// weight_bytes: 2, or 1 for 8-bit weights.
uint64_t CompressedMemory(uint64_t terms, uint64_t receivers, uint64_t clusters, uint64_t r,
                          uint64_t weight_bytes) {
  return 4 * (clusters + 1) + 2 * 3 * terms * clusters * (r + 1) + 8 * 3 * terms +
         weight_bytes * receivers * r;
}

struct Candidate {
  uint32_t cluster_size = 0, components = 0;
  uint8_t weight_bits = 16;
  uint64_t bytes = 0;
  double max_error = 0, mean_error = 0;
};

// The runtime form of clusters `pcas` with r components.
void Quantise(const std::vector<ClusterPca>& pcas, uint32_t r, Index terms, Index receivers,
              uint8_t weight_bits, BakeCompressedBasis* out) {
  const double one = CompressedWeightOne(weight_bits);
  out->weight_bits = weight_bits;
  const Index clusters = static_cast<Index>(pcas.size());
  const Index nv = clusters * (r + 1);
  MatrixXd vecs = MatrixXd::Zero(nv, 3 * terms);
  out->components = r;
  out->cluster_start.assign(1, 0);
  out->weights.assign(static_cast<size_t>(receivers) * r, 0);
  for (Index c = 0; c < clusters; ++c) {
    const ClusterPca& p = pcas[static_cast<size_t>(c)];
    out->cluster_start.push_back(static_cast<uint32_t>(p.start + p.size));
    vecs.row(c * (r + 1)) = p.mean.transpose();
    for (Index j = 0; j < static_cast<Index>(r) && j < p.vectors.cols(); ++j) {
      // Scaled so the largest weight in the cluster is 1 (bake.h).
      const double sigma = p.weights.col(j).cwiseAbs().maxCoeff();
      if (!(sigma > 0)) continue;
      vecs.row(c * (r + 1) + 1 + j) = sigma * p.vectors.col(j).transpose();
      int16_t* w = &out->weights[static_cast<size_t>(p.start) * r + static_cast<size_t>(j * p.size)];
      for (Index i = 0; i < p.size; ++i) {
        const double q = std::round(p.weights(i, j) / sigma * one);
        w[i] = static_cast<int16_t>(std::clamp(q, -one, one));
      }
    }
  }
  out->vectors.assign(static_cast<size_t>(3 * terms * nv), 0);
  out->vector_scale.resize(static_cast<size_t>(3 * terms));
  for (Index t = 0; t < terms; ++t) {
    for (Index c = 0; c < 3; ++c) {
      out->vector_scale[static_cast<size_t>(t * 3 + c)] =
          QuantiseInt16(vecs.col(c * terms + t).data(), static_cast<size_t>(nv), 1,
                        &out->vectors[static_cast<size_t>(t * nv * 3 + c)], 3);
    }
  }
}

}  // namespace

namespace {

// MeasureCompressedError on the stacked basis x, the looks k and their peaks.
void MeasureStacked(const MatrixXd& x, const MatrixXd& k, const VectorXd& peak,
                    const BakeCompressedBasis& cpca, int threads, double* max_error,
                    double* mean_error) {
  const Index terms = k.rows(), receivers = x.rows(), looks = k.cols();
  const uint32_t r = cpca.components;
  const Index nv = static_cast<Index>(cpca.cluster_count()) * (r + 1);
  MatrixXd vecs(nv, 3 * terms);  // dequantised
  for (Index t = 0; t < terms; ++t) {
    for (Index c = 0; c < 3; ++c) {
      const double s = QuantScaleValue(cpca.vector_scale[static_cast<size_t>(t * 3 + c)]);
      for (Index v = 0; v < nv; ++v) vecs(v, c * terms + t) = s * cpca.vectors[static_cast<size_t>((t * nv + v) * 3 + c)];
    }
  }
  // Per cluster and look: the largest and the summed |error| over its
  // receivers and the channels; clusters run in parallel, summed in order.
  const size_t clusters = cpca.cluster_count();
  const double one = CompressedWeightOne(cpca.weight_bits);
  std::vector<VectorXd> cluster_max(clusters), cluster_sum(clusters);
  ParallelFor(clusters, threads, [&](size_t cl, int) {
    const Index s = cpca.cluster_start[cl], n = cpca.cluster_start[cl + 1] - s;
    MatrixXd w(n, r);
    for (uint32_t j = 0; j < r; ++j) {
      for (Index i = 0; i < n; ++i) {
        w(i, j) = cpca.weights[static_cast<size_t>(s * r + j * n + i)] / one;
      }
    }
    const Index row = static_cast<Index>(cl) * (r + 1);
    MatrixXd diff = x.middleRows(s, n);
    if (r > 0) diff -= Multiply(w, vecs.middleRows(row + 1, r));
    diff.rowwise() -= vecs.row(row);
    cluster_max[cl] = VectorXd::Zero(looks);
    cluster_sum[cl] = VectorXd::Zero(looks);
    for (int c = 0; c < 3; ++c) {
      const MatrixXd error = Multiply(diff.middleCols(c * terms, terms), k).cwiseAbs();
      cluster_max[cl] = cluster_max[cl].cwiseMax(error.colwise().maxCoeff().transpose());
      cluster_sum[cl] += error.colwise().sum().transpose();
    }
  });
  double worst = 0, mean = 0;
  int counted = 0;
  for (Index l = 0; l < looks; ++l) {
    if (!(peak(l) > 0)) continue;
    double m = 0, sum = 0;
    for (size_t cl = 0; cl < clusters; ++cl) {
      m = std::max(m, cluster_max[cl](l));
      sum += cluster_sum[cl](l);
    }
    worst = std::max(worst, m / peak(l));
    mean += sum / (3.0 * static_cast<double>(receivers)) / peak(l);
    ++counted;
  }
  *max_error = worst;
  *mean_error = counted > 0 ? mean / counted : 0;
}

}  // namespace

void MeasureCompressedError(const std::array<MatrixXd, 3>& basis, const BakeCompressedBasis& cpca,
                            const std::vector<VectorXd>& looks, const std::vector<MatrixXd>& direct,
                            double* max_error, double* mean_error, int threads) {
  const MatrixXd x = StackChannels(basis);
  const MatrixXd k = LookMatrix(looks, basis[0].cols());
  MeasureStacked(x, k, LookPeaks(x, k, direct, threads), cpca, threads, max_error, mean_error);
}

CompressionStats CompressBasis(const std::array<MatrixXd, 3>& basis, const std::vector<VectorXd>& looks,
                               const std::vector<MatrixXd>& direct, double max_error, int threads,
                               BakeCompressedBasis* out, std::vector<CompressionPoint>* curve,
                               bool try_8bit) {
  const MatrixXd x = StackChannels(basis);
  const Index terms = basis[0].cols(), receivers = x.rows();
  CompressionStats stats;
  stats.bytes = 2 * 3 * static_cast<uint64_t>(terms * receivers) + 8 * 3 * static_cast<uint64_t>(terms);
  if (receivers == 0 || terms == 0 || looks.empty()) return stats;
  const MatrixXd k = LookMatrix(looks, terms);
  const VectorXd peak = LookPeaks(x, k, direct, threads);
  std::vector<uint32_t> sizes;  // lengths that give different cluster counts
  for (uint32_t n : kClusterSizes) {
    if (!sizes.empty() && (receivers + sizes.back() - 1) / sizes.back() == (receivers + n - 1) / n)
      continue;
    sizes.push_back(n);
  }
  // Passing candidates quantised and measured, smallest first: up to
  // kTries of each weight width.
  constexpr int kTries = 4;
  const size_t tries = try_8bit ? 2 * kTries : kTries;
  const uint64_t weight_bytes = try_8bit ? 1 : 2;
  std::vector<std::vector<ClusterPca>> by_size(sizes.size());
  std::vector<Candidate> passing;
  const auto weigh = [&](size_t si) {
    const uint32_t n = sizes[si];
    const std::vector<ClusterPca>& pcas = by_size[si];
    const Index clusters = static_cast<Index>(pcas.size());
    Index rc = 0;
    for (const ClusterPca& p : pcas) rc = std::max(rc, p.max_err.rows() - 1);
    for (Index r = 0; r <= rc; ++r) {
      if (clusters * (r + 1) > receivers + Index{kMaxCompressedComponents} + 1) break;
      Candidate cand;
      cand.cluster_size = n;
      cand.components = static_cast<uint32_t>(r);
      cand.bytes = CompressedMemory(static_cast<uint64_t>(terms), static_cast<uint64_t>(receivers),
                                    static_cast<uint64_t>(clusters), static_cast<uint64_t>(r), 2);
      int counted = 0;
      for (Index l = 0; l < k.cols(); ++l) {
        if (!(peak(l) > 0)) continue;
        double m = 0, sum = 0;
        for (const ClusterPca& p : pcas) {
          const Index rr = std::min(r, p.max_err.rows() - 1);
          m = std::max(m, p.max_err(rr, l));
          sum += p.sum_err(rr, l);
        }
        cand.max_error = std::max(cand.max_error, m / peak(l));
        cand.mean_error += sum / (3.0 * static_cast<double>(receivers)) / peak(l);
        ++counted;
      }
      if (counted > 0) cand.mean_error /= counted;
      if (curve) {
        curve->push_back(CompressionPoint{0, 0, n, static_cast<uint32_t>(clusters), cand.components,
                                          cand.max_error, cand.mean_error, cand.bytes});
      }
      if (cand.max_error <= kQuantisationHeadroom * max_error && cand.bytes < stats.bytes) {
        passing.push_back(cand);
        if (try_8bit && r > 0) {
          // The same form with a byte a weight: smaller, so the ranking
          // below tries it first (fewer clusters with more components tend
          // to win once a component costs a byte a receiver).
          cand.weight_bits = 8;
          cand.bytes = CompressedMemory(static_cast<uint64_t>(terms), static_cast<uint64_t>(receivers),
                                        static_cast<uint64_t>(clusters), static_cast<uint64_t>(r), 1);
          passing.push_back(cand);
        }
      }
    }
  };
  // The longest length first, with every component count. Its passing
  // candidates bound the bytes the search can end with, so the other lengths
  // are fitted only for the component counts that stay within that bound:
  // the same choice, up to rounding, for less work. With a curve wanted,
  // every count.
  {
    std::vector<std::vector<ClusterPca>> longest;
    AllClusterPcas(x, k, {sizes[0]}, {kMaxSearchedComponents}, threads, &longest);
    by_size[0] = std::move(longest[0]);
    weigh(0);
  }
  if (sizes.size() > 1) {
    uint64_t bound = std::numeric_limits<uint64_t>::max();
    if (!curve && passing.size() >= tries) {
      std::vector<uint64_t> bytes;
      for (const Candidate& c : passing) bytes.push_back(c.bytes);
      std::nth_element(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(tries - 1), bytes.end());
      bound = bytes[tries - 1];
    }
    const std::vector<uint32_t> rest(sizes.begin() + 1, sizes.end());
    std::vector<Index> caps;
    for (uint32_t n : rest) {
      const uint64_t clusters = static_cast<uint64_t>((receivers + n - 1) / n);
      Index cap = 0;
      while (cap < kMaxSearchedComponents &&
             CompressedMemory(static_cast<uint64_t>(terms), static_cast<uint64_t>(receivers),
                              clusters, static_cast<uint64_t>(cap + 1), weight_bytes) <= bound)
        ++cap;
      caps.push_back(cap);
    }
    std::vector<std::vector<ClusterPca>> others;
    AllClusterPcas(x, k, rest, caps, threads, &others);
    for (size_t i = 0; i < rest.size(); ++i) {
      by_size[i + 1] = std::move(others[i]);
      weigh(i + 1);
    }
  }
  std::stable_sort(passing.begin(), passing.end(),
                   [](const Candidate& a, const Candidate& b) { return a.bytes < b.bytes; });
  int tried[2] = {0, 0};  // 16-bit, 8-bit
  for (const Candidate& cand : passing) {
    int& count = tried[cand.weight_bits == 8 ? 1 : 0];
    if (count == kTries) continue;
    ++count;
    const size_t s = static_cast<size_t>(std::find(sizes.begin(), sizes.end(), cand.cluster_size) - sizes.begin());
    BakeCompressedBasis cpca;
    Quantise(by_size[s], cand.components, terms, receivers, cand.weight_bits, &cpca);
    double worst = 0, mean = 0;
    MeasureStacked(x, k, peak, cpca, threads, &worst, &mean);
    if (worst > max_error) continue;
    // 8-bit weights also keep the mean within a tenth of the target: issue
    // 13's 1 % max / 0.1 % mean.
    if (cand.weight_bits == 8 && mean > 0.1 * max_error) continue;
    stats.compressed = true;
    stats.clusters = cpca.cluster_count();
    stats.components = cpca.components;
    stats.max_error = worst;
    stats.mean_error = mean;
    stats.bytes = cpca.memory_bytes();
    stats.weight_bits = cpca.weight_bits;
    *out = std::move(cpca);
    return stats;
  }
  return stats;
}

}  // namespace relight::baker
