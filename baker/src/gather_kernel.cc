#include "gather_kernel.h"

// GCC builds one copy of GatherNode per listed x86-64 extension and picks
// the widest the CPU has when the program loads (ifunc). This file is
// compiled with -O3 -ffp-contract=off (CMakeLists.txt): vectorised loops, and
// no multiply-add contraction that would change results between copies.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define RELIGHT_GATHER_CLONES __attribute__((target_clones("avx512f", "avx2", "default")))
#else
#define RELIGHT_GATHER_CLONES
#endif

namespace relight::baker {
namespace {

// One loop body per case so the compiler sees no branch inside it.
template <bool kInner, bool kMoment>
inline void Accumulate(const double* __restrict bq, const double* __restrict muq,
                       const double* __restrict mvq, const float* f, size_t width,
                       double* __restrict a, double* __restrict du, double* __restrict dv) {
  const double f0 = f[0], f1 = f[1], f2 = f[2], f3 = f[3], f4 = f[4];
  for (size_t j = 0; j < width; ++j) {
    const double bj = bq[j];
    double t = a[j] + f0 * bj;
    if constexpr (kMoment) t = t + (f3 * muq[j] + f4 * mvq[j]);
    a[j] = t;
    if constexpr (kInner) {
      du[j] = du[j] + f1 * bj;
      dv[j] = dv[j] + f2 * bj;
    }
  }
}

}  // namespace

RELIGHT_GATHER_CLONES
void GatherNode(const GatherSources& src, const uint32_t* source, const float* factor,
                uint32_t count, bool inner, double* a, double* du, double* dv) {
  const size_t width = src.width;
  for (size_t j = 0; j < width; ++j) a[j] = 0;
  if (inner) {
    for (size_t j = 0; j < width; ++j) du[j] = dv[j] = 0;
  }
  for (uint32_t e = 0; e < count; ++e) {
    const size_t row = static_cast<size_t>(source[e]) * width;
    const float* f = factor + kGatherCoefficients * static_cast<size_t>(e);
    const double* bq = src.b + row;
    const bool moment = f[3] != 0 || f[4] != 0;
    const double* muq = src.mu + row;
    const double* mvq = src.mv + row;
    if (inner) {
      if (moment)
        Accumulate<true, true>(bq, muq, mvq, f, width, a, du, dv);
      else
        Accumulate<true, false>(bq, muq, mvq, f, width, a, du, dv);
    } else {
      if (moment)
        Accumulate<false, true>(bq, muq, mvq, f, width, a, du, dv);
      else
        Accumulate<false, false>(bq, muq, mvq, f, width, a, du, dv);
    }
  }
}

namespace {

// CarryLight for kFrom source rows and kTo receiving rows: fixed counts, so
// the loop over the columns is a plain vector loop.
template <int kFrom, int kTo>
inline void Carry(const double* const* from, const double* from_weight, double* const* to,
                  const double* to_weight, size_t width) {
  for (size_t j = 0; j < width; ++j) {
    double light = 0;
    for (int i = 0; i < kFrom; ++i) light = light + from_weight[i] * from[i][j];
    for (int k = 0; k < kTo; ++k) to[k][j] = to[k][j] + to_weight[k] * light;
  }
}

}  // namespace

RELIGHT_GATHER_CLONES
void CarryLight(const double* const* from, const double* from_weight, int n_from, double* const* to,
                const double* to_weight, int n_to, size_t width) {
  switch (3 * (n_from - 1) + (n_to - 1)) {
    case 0: return Carry<1, 1>(from, from_weight, to, to_weight, width);
    case 1: return Carry<1, 2>(from, from_weight, to, to_weight, width);
    case 2: return Carry<1, 3>(from, from_weight, to, to_weight, width);
    case 3: return Carry<2, 1>(from, from_weight, to, to_weight, width);
    case 4: return Carry<2, 2>(from, from_weight, to, to_weight, width);
    case 5: return Carry<2, 3>(from, from_weight, to, to_weight, width);
    case 6: return Carry<3, 1>(from, from_weight, to, to_weight, width);
    case 7: return Carry<3, 2>(from, from_weight, to, to_weight, width);
    case 8: return Carry<3, 3>(from, from_weight, to, to_weight, width);
    default: return;  // no rows on one side: nothing to carry
  }
}

}  // namespace relight::baker
