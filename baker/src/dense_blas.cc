#include "dense_blas.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <vector>

// Fortran BLAS and LAPACK as Debian's libopenblas-dev (or the reference
// liblapack-dev) export them.
extern "C" {
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k,
            const double* alpha, const double* a, const int* lda, const double* b, const int* ldb,
            const double* beta, double* c, const int* ldc);
void dsyrk_(const char* uplo, const char* trans, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* beta, double* c, const int* ldc);
// The symmetric eigensolver (MRRR). Asked for all pairs: asking for a range
// switches it to bisection, which was slower on the PCA's matrices.
void dsyevr_(const char* jobz, const char* range, const char* uplo, const int* n, double* a,
             const int* lda, const double* vl, const double* vu, const int* il, const int* iu,
             const double* abstol, int* m, double* w, double* z, const int* ldz, int* isuppz,
             double* work, const int* lwork, int* iwork, const int* liwork, int* info);
// OpenBLAS only: weak, so any other BLAS links as well.
void openblas_set_num_threads(int) __attribute__((weak));
}

namespace relight::baker {
namespace {

using Eigen::Index;
using Eigen::MatrixXd;

// OpenBLAS would start threads of its own inside the callers' (the bases'
// clusters already keep every core busy): one each.
[[maybe_unused]] const bool kOneBlasThread = [] {
  if (openblas_set_num_threads) openblas_set_num_threads(1);
  return true;
}();

int Int(Index v) { return static_cast<int>(v); }
// BLAS wants a leading dimension of at least 1, even for an empty matrix.
int Leading(const ConstMatrixRef& m) { return std::max(1, Int(m.outerStride())); }

}  // namespace

MatrixXd Multiply(const ConstMatrixRef& a, const ConstMatrixRef& b, bool transpose_a) {
  const Index m = transpose_a ? a.cols() : a.rows(), k = transpose_a ? a.rows() : a.cols();
  MatrixXd c = MatrixXd::Zero(m, b.cols());
  if (m == 0 || b.cols() == 0 || k == 0) return c;
  const int mi = Int(m), ni = Int(b.cols()), ki = Int(k), lda = Leading(a), ldb = Leading(b);
  const double one = 1, zero = 0;
  dgemm_(transpose_a ? "T" : "N", "N", &mi, &ni, &ki, &one, a.data(), &lda, b.data(), &ldb, &zero,
         c.data(), &mi);
  return c;
}

MatrixXd LowerGram(const ConstMatrixRef& y, bool of_rows) {
  const Index n = of_rows ? y.rows() : y.cols(), k = of_rows ? y.cols() : y.rows();
  MatrixXd g = MatrixXd::Zero(n, n);
  if (n == 0 || k == 0) return g;
  const int ni = Int(n), ki = Int(k), lda = Leading(y);
  const double one = 1, zero = 0;
  // dsyrk: "N" gives y y^T, "T" gives y^T y.
  dsyrk_("L", of_rows ? "N" : "T", &ni, &ki, &one, y.data(), &lda, &zero, g.data(), &ni);
  return g;
}

MatrixXd TopEigenvectors(MatrixXd& g, Index count) {
  const int n = static_cast<int>(g.rows());
  if (count == 0 || n == 0) return MatrixXd(n, 0);
  const MatrixXd original = g;  // dsyevr overwrites g
  MatrixXd z(n, n);
  const int unused_index = 0;
  const double unused_bound = 0, abstol = 0;  // 0: LAPACK's own safe tolerance
  int m = 0, info = 0;
  std::vector<double> w(static_cast<size_t>(n));
  std::vector<int> isuppz(2 * static_cast<size_t>(n));
  double work_size = 0;
  int iwork_size = 0, query = -1;
  dsyevr_("V", "A", "L", &n, g.data(), &n, &unused_bound, &unused_bound, &unused_index,
          &unused_index, &abstol, &m, w.data(), z.data(), &n, isuppz.data(), &work_size, &query,
          &iwork_size, &query, &info);
  int lwork = static_cast<int>(work_size), liwork = iwork_size;
  std::vector<double> work(static_cast<size_t>(std::max(lwork, 1)));
  std::vector<int> iwork(static_cast<size_t>(std::max(liwork, 1)));
  if (info == 0) {
    dsyevr_("V", "A", "L", &n, g.data(), &n, &unused_bound, &unused_bound, &unused_index,
            &unused_index, &abstol, &m, w.data(), z.data(), &n, isuppz.data(), work.data(), &lwork,
            iwork.data(), &liwork, &info);
  }
  if (info != 0 || m != n) {  // not expected for a symmetric matrix: Eigen's then
    Eigen::SelfAdjointEigenSolver<MatrixXd> es(original.selfadjointView<Eigen::Lower>());
    return es.eigenvectors().rightCols(count).rowwise().reverse();
  }
  return z.rightCols(count).rowwise().reverse();  // LAPACK's come in ascending order
}

}  // namespace relight::baker
