// RecombineQ12: see recombine.h for scaling and overflow.
#include "recombine.h"

#include <cstddef>

#include "recombine_avx2.h"
#include "recombine_dispatch.h"
#include "recombine_vnni.h"
#include "relight/base/sh_index.h"
#include "relight/base/status.h"
#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

// One term over one block of receivers: a plain loop over contiguous,
// restrict-qualified arrays with a fixed channel pattern (stride-3 groups,
// widening int16 x int32 -> int64 multiply-accumulate). The runtime is built
// with -mgeneral-regs-only, so no SIMD is emitted there; with vector
// registers allowed, GCC 12 on x86-64 (-O3 -march=haswell) vectorises the
// zeroing and the final shift/saturate loops but keeps this one scalar.
inline void AccumulateTerm(const int16_t* __restrict q, int32_t k0, int32_t k1, int32_t k2,
                           uint32_t n, int64_t* __restrict acc) {
  for (uint32_t i = 0; i < n; ++i) {
    acc[3 * i + 0] += static_cast<int64_t>(q[3 * i + 0]) * k0;
    acc[3 * i + 1] += static_cast<int64_t>(q[3 * i + 1]) * k1;
    acc[3 * i + 2] += static_cast<int64_t>(q[3 * i + 2]) * k2;
  }
}

// Shifts, rounds (halves up) and saturates one block's accumulators.
inline void FinishBlock(const int64_t* acc, uint32_t elements, int shift, int32_t* dst) {
  const int64_t half = shift > 0 ? (int64_t{1} << (shift - 1)) : 0;
  // |acc| < 2^55, so acc + half cannot overflow int64.
  for (uint32_t i = 0; i < elements; ++i) dst[i] = SaturateI32((acc[i] + half) >> shift);
}

// The vector path: AVX2 multiply-adds (or AVX-512 vpdpwssd, the same sums)
// over the active terms, blocks of scratch_len / 3 receivers (one exact
// int64 sum per element).
void RecombineVector(const int16_t* basis, uint32_t receiver_count, const uint16_t* terms,
                     uint32_t term_count, const int32_t* k, int shift, int64_t* scratch,
                     uint32_t scratch_len, int32_t* out) {
  const uint32_t block = scratch_len / 3;
  const bool avx512 = ActiveSimdLevel() == SimdLevel::kAvx512Vnni;
  TermPairVectors pairs[kMaxTermPairs];  // 56 KiB of stack, built once per call
  BuildTermPairsAvx2(terms, term_count, k, pairs);
  for (uint32_t r0 = 0; r0 < receiver_count; r0 += block) {
    const uint32_t n = receiver_count - r0 < block ? receiver_count - r0 : block;
    const int16_t* rows = basis + static_cast<size_t>(r0) * 3;
    const uint64_t stride = static_cast<uint64_t>(receiver_count) * 3;
    if (avx512) {
      AccumulateTermsAvx512Vnni(rows, stride, terms, term_count, pairs, 3 * n, scratch);
      FinishBlockAvx512(scratch, 3 * n, shift, out + static_cast<size_t>(r0) * 3);
    } else {
      AccumulateTermsAvx2(rows, stride, terms, term_count, k, pairs, 3 * n, scratch);
      FinishBlock(scratch, 3 * n, shift, out + static_cast<size_t>(r0) * 3);
    }
  }
}

}  // namespace

uint32_t RecombineQ12(const int16_t* basis, uint32_t term_count, uint32_t receiver_count,
                      const int32_t* k, int shift, int64_t* scratch, uint32_t scratch_len,
                      int32_t* out) {
  RELIGHT_CHECK(scratch_len >= 3);
  RELIGHT_CHECK(shift >= 0 && shift <= 62);
  RELIGHT_CHECK(term_count <= static_cast<uint32_t>(ShTermCount(kMaxShDegree)));
  uint16_t active[ShTermCount(kMaxShDegree)];
  uint32_t used_terms = 0;
  bool vector_ok = true;
  constexpr int32_t kVectorLimit = int32_t{1} << kVectorMultiplierBits;
  for (uint32_t t = 0; t < term_count; ++t) {
    if ((k[3 * t] | k[3 * t + 1] | k[3 * t + 2]) == 0) continue;
    active[used_terms++] = static_cast<uint16_t>(t);
    for (int c = 0; c < 3; ++c) vector_ok = vector_ok && k[3 * t + c] < kVectorLimit && k[3 * t + c] >= -kVectorLimit;
  }
  if (vector_ok && used_terms > 0 && CpuHasAvx2()) {
    RecombineVector(basis, receiver_count, active, used_terms, k, shift, scratch, scratch_len, out);
    return used_terms;
  }
  const uint32_t block = scratch_len / 3;
  for (uint32_t r0 = 0; r0 < receiver_count; r0 += block) {
    const uint32_t n = receiver_count - r0 < block ? receiver_count - r0 : block;
    for (uint32_t i = 0; i < 3 * n; ++i) scratch[i] = 0;
    for (uint32_t t = 0; t < term_count; ++t) {
      const int32_t k0 = k[3 * t], k1 = k[3 * t + 1], k2 = k[3 * t + 2];
      if ((k0 | k1 | k2) == 0) continue;
      const int16_t* q = basis + (static_cast<size_t>(t) * receiver_count + r0) * 3;
      AccumulateTerm(q, k0, k1, k2, n, scratch);
    }
    FinishBlock(scratch, 3 * n, shift, out + static_cast<size_t>(r0) * 3);
  }
  return used_terms;
}

}  // namespace relight
