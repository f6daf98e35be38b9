// The bases' PCA (compress_basis.cc) on LAPACK and BLAS: Debian's OpenBLAS
// runs these products and eigensolves several times faster than Eigen's own
// code in the baseline x86-64 build. Column-major doubles throughout; a
// Ref takes a whole matrix or a block of whole columns or rows.
#pragma once

#include <Eigen/Dense>

namespace relight::baker {

using ConstMatrixRef = Eigen::Ref<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>;

// a b, or a^T b with `transpose_a`.
Eigen::MatrixXd Multiply(const ConstMatrixRef& a, const ConstMatrixRef& b,
                         bool transpose_a = false);

// The Gram matrix y^T y, or y y^T with `of_rows`; only its lower triangle
// is filled (all TopEigenvectors reads).
Eigen::MatrixXd LowerGram(const ConstMatrixRef& y, bool of_rows);

// The `count` unit eigenvectors of the largest eigenvalues of symmetric g
// (its lower triangle is read), largest first; g is overwritten.
Eigen::MatrixXd TopEigenvectors(Eigen::MatrixXd& g, Eigen::Index count);

// Columns added to the subspace LeadingEigenvectors iterates on.
constexpr Eigen::Index kSubspaceOversampling = 16;

// Nearly the `count` leading unit eigenvectors of symmetric positive
// semi-definite g (lower triangle read), largest first, orthonormal: by
// subspace iteration from a fixed start and a Rayleigh-Ritz step (Halko,
// Martinsson & Tropp 2011, "Finding structure with randomness", 4.4 and
// 5.3), all in matrix products. What they miss of g's leading eigenspace
// shrinks with each power step; small g goes to TopEigenvectors.
Eigen::MatrixXd LeadingEigenvectors(const Eigen::MatrixXd& g, Eigen::Index count,
                                    int power_steps);

}  // namespace relight::baker
