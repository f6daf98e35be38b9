// AVX2 gathers for the emitter solve: see surface_emitter_gather_avx2.h.
// Per link: the source's three channels sign-extended to int64 lanes, times
// the factor (and gradients) with _mm256_mul_epi32 (signed 32 x 32 -> 64),
// added in int64 lanes: the scalar path's arithmetic, four lanes at a time.
#include "surface_emitter_gather_avx2.h"

#include "recombine_avx2.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define RELIGHT_HAVE_AVX2_PATH 1
#endif

namespace relight {

bool EmitterGatherHasAvx2() { return CpuHasAvx2(); }

#ifdef RELIGHT_HAVE_AVX2_PATH

namespace {

__attribute__((target("avx2"), always_inline)) inline __m256i Source(const int32_t* view, uint32_t s) {
  return _mm256_cvtepi32_epi64(_mm_loadu_si128(reinterpret_cast<const __m128i*>(view + 4 * size_t{s})));
}

__attribute__((target("avx2"), always_inline)) inline void Store3(__m256i x, int64_t out[3]) {
  alignas(32) int64_t lanes[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), x);
  out[0] = lanes[0];
  out[1] = lanes[1];
  out[2] = lanes[2];
}

}  // namespace

__attribute__((target("avx2"))) void GatherLeafAvx2(const EmitterGatherEntry* e, uint32_t count,
                                                    const int32_t* view, int64_t a[3]) {
  __m256i acc0 = _mm256_setzero_si256(), acc1 = _mm256_setzero_si256();
  uint32_t i = 0;
  for (; i + 1 < count; i += 2) {  // two chains hide the multiply's latency
    acc0 = _mm256_add_epi64(acc0, _mm256_mul_epi32(Source(view, e[i].source),
                                                   _mm256_set1_epi32(static_cast<int32_t>(e[i].f))));
    acc1 = _mm256_add_epi64(acc1, _mm256_mul_epi32(Source(view, e[i + 1].source),
                                                   _mm256_set1_epi32(static_cast<int32_t>(e[i + 1].f))));
  }
  if (i < count)
    acc0 = _mm256_add_epi64(acc0, _mm256_mul_epi32(Source(view, e[i].source),
                                                   _mm256_set1_epi32(static_cast<int32_t>(e[i].f))));
  Store3(_mm256_add_epi64(acc0, acc1), a);
}

__attribute__((target("avx2"))) void GatherInnerAvx2(const EmitterGatherEntry* e, const int32_t* g,
                                                     uint32_t count, const int32_t* view, int64_t a[3],
                                                     int64_t u[3], int64_t v[3]) {
  __m256i sa = _mm256_setzero_si256(), su = _mm256_setzero_si256(), sv = _mm256_setzero_si256();
  for (uint32_t i = 0; i < count; ++i) {
    const __m256i b = Source(view, e[i].source);
    sa = _mm256_add_epi64(sa, _mm256_mul_epi32(b, _mm256_set1_epi32(static_cast<int32_t>(e[i].f))));
    su = _mm256_add_epi64(su, _mm256_mul_epi32(b, _mm256_set1_epi32(g[2 * size_t{i}])));
    sv = _mm256_add_epi64(sv, _mm256_mul_epi32(b, _mm256_set1_epi32(g[2 * size_t{i} + 1])));
  }
  Store3(sa, a);
  Store3(su, u);
  Store3(sv, v);
}

namespace {

__attribute__((target("avx2"), always_inline)) inline void Add3(__m256i x, int64_t out[3]) {
  alignas(32) int64_t lanes[4];
  _mm256_store_si256(reinterpret_cast<__m256i*>(lanes), x);
  out[0] += lanes[0];
  out[1] += lanes[1];
  out[2] += lanes[2];
}

}  // namespace

__attribute__((target("avx2"))) void GatherLeafFromInnerAvx2(const EmitterInnerSourceEntry* e, uint32_t count,
                                                             const int32_t* rows, int64_t a[3], int64_t m[3]) {
  __m256i sa = _mm256_setzero_si256(), su = _mm256_setzero_si256(), sv = _mm256_setzero_si256();
  for (uint32_t i = 0; i < count; ++i) {
    const int32_t* row = rows + kInnerRowInts * size_t{e[i].source};
    sa = _mm256_add_epi64(sa, _mm256_mul_epi32(Source(row, 0), _mm256_set1_epi32(static_cast<int32_t>(e[i].f))));
    su = _mm256_add_epi64(su, _mm256_mul_epi32(Source(row + 4, 0), _mm256_set1_epi32(e[i].wu)));
    sv = _mm256_add_epi64(sv, _mm256_mul_epi32(Source(row + 8, 0), _mm256_set1_epi32(e[i].wv)));
  }
  Add3(sa, a);
  Store3(_mm256_add_epi64(su, sv), m);
}

__attribute__((target("avx2"))) void GatherInnerFromInnerAvx2(const EmitterInnerSourceEntry* e, const int32_t* g,
                                                              uint32_t count, const int32_t* rows, int64_t a[3],
                                                              int64_t u[3], int64_t v[3], int64_t m[3]) {
  __m256i sa = _mm256_setzero_si256(), su = _mm256_setzero_si256(), sv = _mm256_setzero_si256();
  __m256i mu = _mm256_setzero_si256(), mv = _mm256_setzero_si256();
  for (uint32_t i = 0; i < count; ++i) {
    const int32_t* row = rows + kInnerRowInts * size_t{e[i].source};
    const __m256i b = Source(row, 0);
    sa = _mm256_add_epi64(sa, _mm256_mul_epi32(b, _mm256_set1_epi32(static_cast<int32_t>(e[i].f))));
    su = _mm256_add_epi64(su, _mm256_mul_epi32(b, _mm256_set1_epi32(g[2 * size_t{i}])));
    sv = _mm256_add_epi64(sv, _mm256_mul_epi32(b, _mm256_set1_epi32(g[2 * size_t{i} + 1])));
    mu = _mm256_add_epi64(mu, _mm256_mul_epi32(Source(row + 4, 0), _mm256_set1_epi32(e[i].wu)));
    mv = _mm256_add_epi64(mv, _mm256_mul_epi32(Source(row + 8, 0), _mm256_set1_epi32(e[i].wv)));
  }
  Add3(sa, a);
  Add3(su, u);
  Add3(sv, v);
  Store3(_mm256_add_epi64(mu, mv), m);
}

#else  // no AVX2 path on this target: the solve stays scalar

void GatherLeafAvx2(const EmitterGatherEntry*, uint32_t, const int32_t*, int64_t*) {}
void GatherInnerAvx2(const EmitterGatherEntry*, const int32_t*, uint32_t, const int32_t*, int64_t*, int64_t*,
                     int64_t*) {}
void GatherLeafFromInnerAvx2(const EmitterInnerSourceEntry*, uint32_t, const int32_t*, int64_t*, int64_t*) {}
void GatherInnerFromInnerAvx2(const EmitterInnerSourceEntry*, const int32_t*, uint32_t, const int32_t*, int64_t*,
                              int64_t*, int64_t*, int64_t*) {}

#endif

}  // namespace relight
