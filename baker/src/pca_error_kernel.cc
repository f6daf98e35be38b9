#include "pca_error_kernel.h"

#include <algorithm>
#include <cmath>

// One copy per listed x86-64 extension, the widest the CPU has picked at load
// (as gather_kernel.cc); compiled with -O3 -ffp-contract=off (CMakeLists.txt).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define RELIGHT_PCA_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define RELIGHT_PCA_CLONES
#endif

namespace relight::baker {
namespace {

// Eight lanes: one AVX-512 vector, two AVX2 or four SSE2 ones.
constexpr size_t kLanes = 8;

template <bool kSubtract>
inline AbsStats Pass(double* __restrict v, const double* __restrict w, double a, size_t n) {
  double m[kLanes] = {}, s[kLanes] = {};
  size_t i = 0;
  for (; i + kLanes <= n; i += kLanes) {
    for (size_t j = 0; j < kLanes; ++j) {
      double e = v[i + j];
      if constexpr (kSubtract) {
        e = e - a * w[i + j];
        v[i + j] = e;
      }
      e = std::fabs(e);
      m[j] = m[j] > e ? m[j] : e;
      s[j] = s[j] + e;
    }
  }
  for (; i < n; ++i) {  // the tail in lane 0
    double e = v[i];
    if constexpr (kSubtract) {
      e = e - a * w[i];
      v[i] = e;
    }
    e = std::fabs(e);
    m[0] = m[0] > e ? m[0] : e;
    s[0] = s[0] + e;
  }
  AbsStats out;
  for (size_t j = 0; j < kLanes; ++j) out.max = std::max(out.max, m[j]);
  out.sum = ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
  return out;
}

}  // namespace

RELIGHT_PCA_CLONES
AbsStats SubtractAndMeasure(double* v, const double* w, double a, size_t n) {
  return w != nullptr ? Pass<true>(v, w, a, n) : Pass<false>(v, w, a, n);
}

}  // namespace relight::baker
