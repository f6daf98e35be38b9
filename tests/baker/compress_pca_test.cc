// The bases' PCA on LAPACK (baker/src/dense_blas.cc) and its use in the
// clustered compression (compress_basis.cc): the top eigenvectors agree with
// Eigen's full eigensolver, and the compression is the same with one thread
// or two (the error measurement runs per cluster in parallel).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "compress_basis.h"
#include "dense_blas.h"

namespace relight::baker {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;
using Eigen::VectorXd;

// rows x cols of smooth low-rank data plus a little noise: what a cluster
// of a luminaire's basis looks like to the PCA.
MatrixXd LowRankData(Index rows, Index cols, Index rank, uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  MatrixXd a(rows, rank), b(rank, cols), noise(rows, cols);
  for (Index i = 0; i < a.size(); ++i) a.data()[i] = normal(rng);
  for (Index i = 0; i < b.size(); ++i)
    b.data()[i] = normal(rng) / static_cast<double>(1 + i % rank);
  for (Index i = 0; i < noise.size(); ++i) noise.data()[i] = 1e-3 * normal(rng);
  return a * b + noise;
}

TEST(DenseBlas, TopEigenvectorsMatchEigensFullSolver) {
  const Index d = 243,
              count = 32;  // a degree-8 luminaire's 3 x 81 terms, the most components searched
  const MatrixXd y = LowRankData(512, d, 40, 7);
  MatrixXd gram = LowerGram(y, false);
  const MatrixXd full = y.transpose() * y;
  const MatrixXd top = TopEigenvectors(gram, count);
  ASSERT_EQ(top.rows(), d);
  ASSERT_EQ(top.cols(), count);
  Eigen::SelfAdjointEigenSolver<MatrixXd> reference(full);
  const VectorXd values = reference.eigenvalues().reverse();  // largest first
  for (Index j = 0; j < count; ++j) {
    const VectorXd v = top.col(j);
    EXPECT_NEAR(v.norm(), 1.0, 1e-12) << "vector " << j;
    // An eigenvector of the j-th largest eigenvalue (sign free): its
    // residual is small against that eigenvalue.
    const double residual = (full * v - values(j) * v).norm();
    EXPECT_LT(residual, 1e-9 * values(0)) << "vector " << j;
    const VectorXd ref = reference.eigenvectors().col(d - 1 - j);
    EXPECT_NEAR(std::abs(v.dot(ref)), 1.0, 1e-8) << "vector " << j;
  }
}

TEST(DenseBlas, TopEigenvectorsOfASmallMatrixAskedForAll) {
  MatrixXd g(3, 3);
  g << 4, 0, 0, 1, 3, 0, 0, 1, 2;  // lower triangle of a symmetric matrix
  const MatrixXd full = g.selfadjointView<Eigen::Lower>();
  MatrixXd work = g;
  const MatrixXd top = TopEigenvectors(work, 5);  // more than there are: all 3
  ASSERT_EQ(top.cols(), 3);
  Eigen::SelfAdjointEigenSolver<MatrixXd> reference(full);
  for (Index j = 0; j < 3; ++j) {
    const double lambda = reference.eigenvalues()(2 - j);
    EXPECT_LT((full * top.col(j) - lambda * top.col(j)).norm(), 1e-12) << "vector " << j;
  }
}

TEST(DenseBlas, TopEigenvectorsOfZeroAndOneByOneMatrices) {
  // A cluster whose receivers all have the same basis (an unlit corner):
  // after the mean is taken out its Gram matrix is zero. Any orthonormal
  // vectors will do, but they must be unit and finite.
  MatrixXd zero = MatrixXd::Zero(243, 243);
  const MatrixXd top = TopEigenvectors(zero, 32);
  ASSERT_EQ(top.cols(), 32);
  ASSERT_TRUE(top.allFinite());
  const MatrixXd gram = top.transpose() * top;
  EXPECT_LT((gram - MatrixXd::Identity(32, 32)).cwiseAbs().maxCoeff(), 1e-12);
  // A cluster of one receiver (the last of a basis 2049 receivers long).
  MatrixXd one(1, 1);
  one << 2.5;
  const MatrixXd v = TopEigenvectors(one, 32);
  ASSERT_EQ(v.rows(), 1);
  ASSERT_EQ(v.cols(), 1);
  EXPECT_DOUBLE_EQ(std::abs(v(0, 0)), 1.0);
}

TEST(CompressBasis, SameResultWithOneThreadOrTwo) {
  // Three channels of 1500 receivers x 25 terms (degree 4).
  const Index receivers = 1500, terms = 25;
  const MatrixXd all = LowRankData(receivers, 3 * terms, 6, 11);
  std::array<MatrixXd, 3> basis;
  for (int c = 0; c < 3; ++c) basis[c] = all.middleCols(c * terms, terms);
  std::mt19937 rng(3);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<VectorXd> looks(8, VectorXd(terms));
  for (VectorXd& l : looks)
    for (Index t = 0; t < terms; ++t) l(t) = normal(rng);
  BakeCompressedBasis one, two;
  const CompressionStats a = CompressBasis(basis, looks, {}, 0.01, 1, &one);
  const CompressionStats b = CompressBasis(basis, looks, {}, 0.01, 2, &two);
  ASSERT_TRUE(a.compressed);
  EXPECT_EQ(a.max_error, b.max_error);
  EXPECT_EQ(a.mean_error, b.mean_error);
  EXPECT_EQ(a.clusters, b.clusters);
  EXPECT_EQ(a.components, b.components);
  EXPECT_EQ(one.weights, two.weights);
  EXPECT_EQ(one.vectors, two.vectors);
  EXPECT_LE(a.max_error, 0.01);
  // The stored form, measured again on its own, gives the figure the search reported.
  double max_error = 0, mean_error = 0;
  MeasureCompressedError(basis, one, looks, {}, &max_error, &mean_error, 2);
  EXPECT_EQ(max_error, a.max_error);
  EXPECT_EQ(mean_error, a.mean_error);
}

}  // namespace
}  // namespace relight::baker
