// Clustered PCA of a basis, cluster by cluster (cluster_pca.h).
#include "cluster_pca.h"

#include <algorithm>

#include "dense_blas.h"
#include "parallel_for.h"
#include "pca_error_kernel.h"

namespace relight::baker {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// The run of receivers [start, start + count): its mean and the lower
// triangle of its centred Gram matrix (3T x 3T).
struct RunMoments {
  Index start = 0, count = 0;
  VectorXd mean;
  MatrixXd gram;
};

// Rows [start, start + count) of x less their mean (returned in `mean`).
MatrixXd CentredRows(const MatrixXd& x, Index start, Index count, VectorXd* mean) {
  MatrixXd y = x.middleRows(start, count);
  *mean = y.colwise().mean().transpose();
  y.rowwise() -= mean->transpose();
  return y;
}

RunMoments Moments(const MatrixXd& x, Index start, Index count) {
  RunMoments m;
  m.start = start;
  m.count = count;
  m.gram = LowerGram(CentredRows(x, start, count, &m.mean), false);
  return m;
}

// Two adjacent runs as one, from their moments alone (the pairwise update
// of Chan, Golub & LeVeque 1979): the longer cluster lengths cost no pass
// over the receivers.
RunMoments Merge(const RunMoments& a, const RunMoments& b) {
  RunMoments m;
  m.start = a.start;
  m.count = a.count + b.count;
  const VectorXd delta = b.mean - a.mean;
  const double na = static_cast<double>(a.count), nb = static_cast<double>(b.count);
  m.mean = a.mean + (nb / (na + nb)) * delta;
  m.gram = a.gram + b.gram;
  m.gram.selfadjointView<Eigen::Lower>().rankUpdate(delta, na * nb / (na + nb));
  return m;
}

// Subspace iteration's power steps for the principal directions: one gives
// the venue's bases the same size in memory as exact eigenvectors did, for
// less work than two (docs/venue.md).
constexpr int kPowerSteps = 1;

// Weights and the errors at the looks of a cluster whose mean and
// principal directions are set, read from the uncentred rows of x.
void FitCluster(const MatrixXd& x, const MatrixXd& k, ClusterPca* p) {
  const auto rows = x.middleRows(p->start, p->size);
  const Index rc = p->vectors.cols();
  p->weights = Multiply(rows, p->vectors);
  p->weights.rowwise() -= p->mean.transpose() * p->vectors;
  // Errors at the looks for r = 0 .. rc, channel by channel: a look's
  // residual column (in L1) loses one component per pass.
  const Index t = k.rows(), looks = k.cols();
  p->max_err = MatrixXd::Zero(rc + 1, looks);
  p->sum_err = MatrixXd::Zero(rc + 1, looks);
  for (int c = 0; c < 3; ++c) {
    MatrixXd residual = Multiply(rows.middleCols(c * t, t), k);  // size x looks
    residual.rowwise() -= p->mean.segment(c * t, t).transpose() * k;
    const MatrixXd f = Multiply(p->vectors.middleRows(c * t, t), k, true);  // rc x looks
    for (Index l = 0; l < looks; ++l) {
      double* column = residual.col(l).data();
      for (Index r = 0; r <= rc; ++r) {
        const double* w = r > 0 ? p->weights.col(r - 1).data() : nullptr;
        const AbsStats e = SubtractAndMeasure(column, w, r > 0 ? f(r - 1, l) : 0.0,
                                              static_cast<size_t>(p->size));
        p->max_err(r, l) = std::max(p->max_err(r, l), e.max);
        p->sum_err(r, l) += e.sum;
      }
    }
  }
}

// A cluster of at least 3T receivers, from its moments: its directions,
// weights and errors for at most `cap` components (the subspace iteration
// then works on cap + 16 columns, so the directions' rounding depends on
// the cap).
ClusterPca PcaOfMoments(const MatrixXd& x, const RunMoments& m, Index cap, const MatrixXd& k) {
  ClusterPca p;
  p.start = m.start;
  p.size = m.count;
  p.mean = m.mean;
  const Index rc = std::min({cap, m.count, x.cols()});
  p.vectors = LeadingEigenvectors(m.gram, rc, kPowerSteps);
  FitCluster(x, k, &p);
  return p;
}

// A cluster of fewer receivers than 3T: its rows' Gram matrix is the
// smaller. `cap` as PcaOfMoments.
ClusterPca PcaOfFewRows(const MatrixXd& x, Index start, Index size, Index cap, const MatrixXd& k) {
  ClusterPca p;
  p.start = start;
  p.size = size;
  const MatrixXd y = CentredRows(x, start, size, &p.mean);
  const Index d = y.cols(), rc = std::min({cap, size, d});
  // y^T u is along the principal direction of u, scaled by its singular
  // value; made orthonormal in order (Householder QR), since beyond the
  // cluster's rank those values are rounding noise and y^T u points anywhere.
  const MatrixXd directions =
      Multiply(y, LeadingEigenvectors(LowerGram(y, true), rc, kPowerSteps), true);
  const Eigen::HouseholderQR<MatrixXd> qr(directions);
  p.vectors = qr.householderQ() * MatrixXd::Identity(d, rc);
  FitCluster(x, k, &p);
  return p;
}

}  // namespace

// Tasks take one run of the longest length: its shortest clusters of at
// least 3T receivers get their moments from the receivers, the longer ones
// by merging pairs.
void AllClusterPcas(const MatrixXd& x, const MatrixXd& k, const std::vector<uint32_t>& sizes,
                    const std::vector<Index>& caps, int threads,
                    std::vector<std::vector<ClusterPca>>* pcas) {
  const Index receivers = x.rows(), d = x.cols();
  const Index longest = kClusterSizes[0];
  Index base = 0;  // the shortest length of at least d receivers (0: none is)
  for (uint32_t n : kClusterSizes)
    if (static_cast<Index>(n) >= d) base = n;
  pcas->assign(sizes.size(), {});
  for (size_t i = 0; i < sizes.size(); ++i)
    (*pcas)[i].resize(static_cast<size_t>((receivers + sizes[i] - 1) / sizes[i]));
  const auto index_of = [&](Index length) {
    return static_cast<size_t>(std::find(sizes.begin(), sizes.end(), length) - sizes.begin());
  };
  // nullptr: a length not asked for (or that gives the same clusters as a longer one).
  const auto slot = [&](Index length, Index start) -> ClusterPca* {
    const size_t i = index_of(length);
    return i < sizes.size() ? &(*pcas)[i][static_cast<size_t>(start / length)] : nullptr;
  };
  const auto cap = [&](Index length) { return caps[index_of(length)]; };
  const size_t runs = static_cast<size_t>((receivers + longest - 1) / longest);
  ParallelFor(runs, threads, [&](size_t run, int) {
    const Index begin = static_cast<Index>(run) * longest;
    const Index end = std::min(begin + longest, receivers);
    for (uint32_t n : sizes) {  // lengths shorter than 3T
      const Index length = n;
      if (base > 0 && length >= base) continue;
      for (Index s = begin; s < end; s += length)
        *slot(length, s) = PcaOfFewRows(x, s, std::min(length, end - s), cap(length), k);
    }
    if (base == 0) return;
    std::vector<RunMoments> level;
    for (Index s = begin; s < end; s += base) level.push_back(Moments(x, s, std::min(base, end - s)));
    for (Index length = base;; length *= 2) {
      for (const RunMoments& m : level) {
        if (ClusterPca* out = slot(length, m.start)) {
          *out = m.count >= d ? PcaOfMoments(x, m, cap(length), k)
                              : PcaOfFewRows(x, m.start, m.count, cap(length), k);
        }
      }
      if (length >= longest) break;
      std::vector<RunMoments> up;
      for (size_t j = 0; j < level.size(); j += 2)
        up.push_back(j + 1 < level.size() ? Merge(level[j], level[j + 1]) : std::move(level[j]));
      level = std::move(up);
    }
  });
}

}  // namespace relight::baker
