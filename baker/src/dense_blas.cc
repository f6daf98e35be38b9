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
// The symmetric eigenproblem in its three steps, so that only the few
// eigenvectors the PCA keeps are transformed back: reduction to tridiagonal
// form, every eigenpair of that by MRRR (dstemr), and the
// back-transformation of the kept ones (dsyevr would transform them all).
void dsytrd_(const char* uplo, const int* n, double* a, const int* lda, double* d, double* e,
             double* tau, double* work, const int* lwork, int* info);
void dstemr_(const char* jobz, const char* range, const int* n, double* d, double* e,
             const double* vl, const double* vu, const int* il, const int* iu, int* m, double* w,
             double* z, const int* ldz, const int* nzc, int* isuppz, int* tryrac, double* work,
             const int* lwork, int* iwork, const int* liwork, int* info);
void dormtr_(const char* side, const char* uplo, const char* trans, const int* m, const int* n,
             const double* a, const int* lda, const double* tau, double* c, const int* ldc,
             double* work, const int* lwork, int* info);
void dsymm_(const char* side, const char* uplo, const int* m, const int* n, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta,
            double* c, const int* ldc);
void dgeqrf_(const int* m, const int* n, double* a, const int* lda, double* tau, double* work,
             const int* lwork, int* info);
void dorgqr_(const int* m, const int* n, const int* k, double* a, const int* lda,
             const double* tau, double* work, const int* lwork, int* info);
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
  count = std::min<Index>(count, n);
  if (count == 0 || n == 0) return MatrixXd(n, 0);
  const MatrixXd original = g;  // dsytrd overwrites g
  const auto fallback = [&] {  // not expected for a symmetric matrix: Eigen's then
    Eigen::SelfAdjointEigenSolver<MatrixXd> es(original.selfadjointView<Eigen::Lower>());
    return MatrixXd(es.eigenvectors().rightCols(count).rowwise().reverse());
  };
  const int wanted = static_cast<int>(count), query = -1;
  std::vector<double> d(static_cast<size_t>(n)), e(static_cast<size_t>(n)),
      tau(static_cast<size_t>(n));
  int info = 0;
  double size = 0;
  dsytrd_("L", &n, g.data(), &n, d.data(), e.data(), tau.data(), &size, &query, &info);
  if (info != 0) return fallback();
  std::vector<double> work(static_cast<size_t>(std::max(1.0, size)));
  int lwork = static_cast<int>(work.size());
  dsytrd_("L", &n, g.data(), &n, d.data(), e.data(), tau.data(), work.data(), &lwork, &info);
  if (info != 0) return fallback();
  // Every eigenpair of the tridiagonal matrix (O(n^2) by MRRR; a range of
  // indices would make dstemr find the eigenvalues by bisection, slower
  // here), then the `count` largest (the last columns) transformed back.
  const double unused_bound = 0;
  const int unused_index = 0;
  int m = 0, tryrac = 1, iwork_size = 0;
  MatrixXd all(n, n);
  std::vector<double> w(static_cast<size_t>(n));
  std::vector<int> isuppz(2 * static_cast<size_t>(n));
  dstemr_("V", "A", &n, d.data(), e.data(), &unused_bound, &unused_bound, &unused_index,
          &unused_index, &m, w.data(), all.data(), &n, &n, isuppz.data(), &tryrac, &size, &query,
          &iwork_size, &query, &info);
  if (info != 0) return fallback();
  work.assign(static_cast<size_t>(std::max(1.0, size)), 0.0);
  std::vector<int> iwork(static_cast<size_t>(std::max(1, iwork_size)));
  lwork = static_cast<int>(work.size());
  int liwork = static_cast<int>(iwork.size());
  dstemr_("V", "A", &n, d.data(), e.data(), &unused_bound, &unused_bound, &unused_index,
          &unused_index, &m, w.data(), all.data(), &n, &n, isuppz.data(), &tryrac, work.data(),
          &lwork, iwork.data(), &liwork, &info);
  if (info != 0 || m != n) return fallback();
  MatrixXd z = all.rightCols(count);
  dormtr_("L", "L", "N", &n, &wanted, g.data(), &n, tau.data(), z.data(), &n, &size, &query, &info);
  if (info != 0) return fallback();
  work.assign(static_cast<size_t>(std::max(1.0, size)), 0.0);
  lwork = static_cast<int>(work.size());
  dormtr_("L", "L", "N", &n, &wanted, g.data(), &n, tau.data(), z.data(), &n, work.data(), &lwork,
          &info);
  if (info != 0) return fallback();
  return z.rowwise().reverse();  // largest first (LAPACK's come ascending)
}

namespace {

// y = g q for symmetric g (lower triangle).
void SymmetricProduct(const MatrixXd& g, const MatrixXd& q, MatrixXd* y) {
  const int n = Int(g.rows()), l = Int(q.cols());
  const double one = 1, zero = 0;
  y->resize(g.rows(), q.cols());
  dsymm_("L", "L", &n, &l, &one, g.data(), &n, q.data(), &n, &zero, y->data(), &n);
}

// q's columns replaced by an orthonormal basis of their span (Householder
// QR); false when LAPACK refuses.
bool Orthonormalise(MatrixXd* q) {
  const int m = Int(q->rows()), l = Int(q->cols()), query = -1;
  std::vector<double> tau(static_cast<size_t>(l));
  double size = 0, size2 = 0;
  int info = 0;
  dgeqrf_(&m, &l, q->data(), &m, tau.data(), &size, &query, &info);
  if (info != 0) return false;
  dorgqr_(&m, &l, &l, q->data(), &m, tau.data(), &size2, &query, &info);
  if (info != 0) return false;
  std::vector<double> work(static_cast<size_t>(std::max({1.0, size, size2})));
  const int lwork = static_cast<int>(work.size());
  dgeqrf_(&m, &l, q->data(), &m, tau.data(), work.data(), &lwork, &info);
  if (info != 0) return false;
  dorgqr_(&m, &l, &l, q->data(), &m, tau.data(), work.data(), &lwork, &info);
  return info == 0;
}

}  // namespace

MatrixXd LeadingEigenvectors(const MatrixXd& g, Index count, int power_steps) {
  const Index n = g.rows();
  count = std::min<Index>(count, n);
  const Index l = std::min<Index>(n, count + kSubspaceOversampling);
  if (count == 0 || 2 * l > n) {  // small: the exact route is as cheap
    MatrixXd copy = g;
    return TopEigenvectors(copy, count);
  }
  // A fixed start (splitmix64 to uniform [-1, 1)), the same on every
  // machine, so bakes are reproducible.
  MatrixXd q(n, l);
  uint64_t state = 0x9e3779b97f4a7c15ull;
  for (Index i = 0; i < q.size(); ++i) {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    q.data()[i] = static_cast<double>(z >> 11) * 0x1.0p-52 - 1.0;
  }
  MatrixXd y;
  for (int step = 0; step <= power_steps; ++step) {
    SymmetricProduct(g, q, &y);
    q.swap(y);
    if (!Orthonormalise(&q)) {
      MatrixXd copy = g;
      return TopEigenvectors(copy, count);
    }
  }
  // Rayleigh-Ritz on the subspace: the l x l matrix q^T g q, its leading
  // eigenvectors taken back.
  SymmetricProduct(g, q, &y);
  MatrixXd small = Multiply(q, y, true);
  small = (0.5 * (small + small.transpose())).eval();
  const MatrixXd top = TopEigenvectors(small, count);
  return Multiply(q, top);
}

}  // namespace relight::baker
