// VNNI bodies of CompressedClusterQ12: see compressed_recombine_vnni.h.
// Integer instructions only (vpdpwssd, int32 adds and shifts, permutes,
// masked loads and stores).
#include "compressed_recombine_vnni.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>

// GCC 12's AVX-512 headers fill unused merge operands with
// _mm512_undefined_*(), a self-initialised variable that -Wmaybe-uninitialized
// reports once inlined here (a header artefact: every lane is written).
#if !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#include "compressed_recombine_interleave.h"

#define RELIGHT_TARGET_AVX512_VNNI __attribute__((target("avx2,avx512f,avx512bw,avx512vl,avx512vnni")))
#define RELIGHT_TARGET_AVX_VNNI __attribute__((target("avx2,avxvnni")))

namespace relight {
namespace {

using cpca_simd::PairMultipliers;

// Permute indices (vpermt2d: 0..15 the first source, 16..31 the second).
struct Indices {
  // R, G, B of 16 receivers in order -> output vector v (elements 16v ..
  // 16v + 15 of the 48, element g = receiver g / 3, channel g % 3): first
  // R and G (rg[v]), then B into that (b[v]).
  int32_t rg[3][16];
  int32_t b[3][16];
  constexpr Indices() : rg(), b() {
    for (int v = 0; v < 3; ++v) {
      for (int e = 0; e < 16; ++e) {
        const int g = 16 * v + e, i = g / 3, c = g % 3;
        rg[v][e] = c == 0 ? i : (c == 1 ? 16 + i : 0);
        b[v][e] = c == 2 ? 16 + i : e;
      }
    }
  }
};
alignas(64) constexpr Indices kIndices;

RELIGHT_TARGET_AVX512_VNNI inline __m512i Load(const int32_t* p) { return _mm512_loadu_si512(p); }

// R, G, B of `count` receivers (1 .. 16, in order) -> 3 count interleaved int32.
RELIGHT_TARGET_AVX512_VNNI inline void StoreRgb(const __m512i* rgb, uint32_t count, int32_t* out) {
  const int elements = 3 * static_cast<int>(count);
  for (int v = 0; v < 3; ++v) {
    const __m512i t = _mm512_permutex2var_epi32(rgb[0], Load(kIndices.rg[v]), rgb[1]);
    const __m512i o = _mm512_permutex2var_epi32(t, Load(kIndices.b[v]), rgb[2]);
    const int left = elements - 16 * v;
    if (left >= 16) {
      _mm512_storeu_si512(out + 16 * v, o);
    } else if (left > 0) {
      _mm512_mask_storeu_epi32(out + 16 * v, static_cast<__mmask16>((1u << left) - 1), o);
    }
  }
}

// A full tile's R, G, B (16 receivers each, in order) -> 48 interleaved
// int32, from values: StoreRgb's pointer made GCC put its three vectors on
// the stack and read them back (stop 44).
RELIGHT_TARGET_AVX512_VNNI inline void StoreRgb16(__m512i r, __m512i g, __m512i b, int32_t* out) {
  for (int v = 0; v < 3; ++v) {
    const __m512i t = _mm512_permutex2var_epi32(r, Load(kIndices.rg[v]), g);
    _mm512_storeu_si512(out + 16 * v, _mm512_permutex2var_epi32(t, Load(kIndices.b[v]), b));
  }
}

// Loads of one tile's weights as the int16 pairs vpdpwssd takes, from int16
// or int8 weights (sign-extended: the same values). Pairs: 16 receivers'
// pair p (32 weights), or `count` receivers' (masked). Last: an odd r's
// last weight, one a 32-bit lane with the weight in the low half; int16
// zero-extends, int8 sign-extends (the high half then may be -1, which the
// multiplier pair (K, 0) ignores).
RELIGHT_TARGET_AVX512_VNNI inline __m512i LoadPairs(const int16_t* p) { return _mm512_loadu_si512(p); }
RELIGHT_TARGET_AVX512_VNNI inline __m512i LoadPairs(const int8_t* p) {
  return _mm512_cvtepi8_epi16(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)));
}
RELIGHT_TARGET_AVX512_VNNI inline __m512i LoadPairs(const int16_t* p, uint32_t count) {
  return _mm512_maskz_loadu_epi16(static_cast<__mmask32>((1u << (2 * count)) - 1), p);  // count < 16
}
RELIGHT_TARGET_AVX512_VNNI inline __m512i LoadPairs(const int8_t* p, uint32_t count) {
  return _mm512_cvtepi8_epi16(_mm256_maskz_loadu_epi8(static_cast<__mmask32>((1u << (2 * count)) - 1), p));
}
RELIGHT_TARGET_AVX512_VNNI inline __m512i LoadLast(const int16_t* p) {
  return _mm512_cvtepu16_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)));
}
RELIGHT_TARGET_AVX512_VNNI inline __m512i LoadLast(const int8_t* p) {
  return _mm512_cvtepi8_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}
RELIGHT_TARGET_AVX512_VNNI inline __m512i LoadLast(const int16_t* p, uint32_t count) {
  return _mm512_cvtepu16_epi32(_mm256_maskz_loadu_epi16(static_cast<__mmask16>((1u << count) - 1), p));
}
RELIGHT_TARGET_AVX512_VNNI inline __m512i LoadLast(const int8_t* p, uint32_t count) {
  return _mm512_cvtepi8_epi32(_mm_maskz_loadu_epi8(static_cast<__mmask16>((1u << count) - 1), p));
}

// One tile of `count` receivers (1 .. 16; compressed_tiles.h) into acc[3]:
// plain loads for a full tile, masked ones for the cluster's short last tile.
template <typename W>
RELIGHT_TARGET_AVX512_VNNI inline void AccumulateTile(const W* tile, uint32_t count,
                                                      uint32_t components,
                                                      const int32_t (*k)[kMaxCompressedComponents / 2 + 1],
                                                      __m512i* acc) {
  const uint32_t pairs = components / 2;
  if (count == 16) {
    for (uint32_t p = 0; p < pairs; ++p) {
      const __m512i v = LoadPairs(tile + 32 * p);
      for (int ch = 0; ch < 3; ++ch) acc[ch] = _mm512_dpwssd_epi32(acc[ch], v, _mm512_set1_epi32(k[ch][p]));
    }
    if (components % 2 != 0) {
      const __m512i v = LoadLast(tile + 32 * pairs);
      for (int ch = 0; ch < 3; ++ch) acc[ch] = _mm512_dpwssd_epi32(acc[ch], v, _mm512_set1_epi32(k[ch][pairs]));
    }
    return;
  }
  for (uint32_t p = 0; p < pairs; ++p) {
    const __m512i v = LoadPairs(tile + size_t{2 * count} * p, count);
    for (int ch = 0; ch < 3; ++ch) acc[ch] = _mm512_dpwssd_epi32(acc[ch], v, _mm512_set1_epi32(k[ch][p]));
  }
  if (components % 2 != 0) {
    const __m512i v = LoadLast(tile + size_t{2 * count} * pairs, count);
    for (int ch = 0; ch < 3; ++ch) acc[ch] = _mm512_dpwssd_epi32(acc[ch], v, _mm512_set1_epi32(k[ch][pairs]));
  }
}

// One channel's finish (compressed_recombine.h): mean + (acc + half) >> s
// for s >= 0 (half is already in acc); for s < 0 (a bright cluster: the
// multipliers took a left shift) mean + acc 2^-s in int64, saturated to
// int32 like the scalar path.
struct ChannelFinish {
  __m512i mean, mean64;
  __m128i shift;
  bool left = false;
};

RELIGHT_TARGET_AVX512_VNNI inline __m512i Finish(__m512i acc, const ChannelFinish& f) {
  if (!f.left) return _mm512_add_epi32(f.mean, _mm512_sra_epi32(acc, f.shift));
  // |acc| < 2^30, shifted by at most 31, plus |mean| < 2^30: within int64.
  const __m512i wide_lo = _mm512_cvtepi32_epi64(_mm512_castsi512_si256(acc));
  const __m512i wide_hi = _mm512_cvtepi32_epi64(_mm512_extracti64x4_epi64(acc, 1));
  const __m256i lo = _mm512_cvtsepi64_epi32(_mm512_add_epi64(f.mean64, _mm512_sll_epi64(wide_lo, f.shift)));
  const __m256i hi = _mm512_cvtsepi64_epi32(_mm512_add_epi64(f.mean64, _mm512_sll_epi64(wide_hi, f.shift)));
  return _mm512_inserti64x4(_mm512_castsi256_si512(lo), hi, 1);
}

// One component pair of both tiles (va, vb: their weights) into the six chains.
RELIGHT_TARGET_AVX512_VNNI __attribute__((always_inline)) inline void PairStep(
    __m512i va, __m512i vb, const int32_t (*k)[kMaxCompressedComponents / 2 + 1], uint32_t p, __m512i& a0,
    __m512i& a1, __m512i& a2, __m512i& b0, __m512i& b1, __m512i& b2) {
  const __m512i k0 = _mm512_set1_epi32(k[0][p]), k1 = _mm512_set1_epi32(k[1][p]), k2 = _mm512_set1_epi32(k[2][p]);
  a0 = _mm512_dpwssd_epi32(a0, va, k0);
  b0 = _mm512_dpwssd_epi32(b0, vb, k0);
  a1 = _mm512_dpwssd_epi32(a1, va, k1);
  b1 = _mm512_dpwssd_epi32(b1, vb, k1);
  a2 = _mm512_dpwssd_epi32(a2, va, k2);
  b2 = _mm512_dpwssd_epi32(b2, vb, k2);
}

// Two full tiles (32 receivers), finished and stored at out: one loop over the
// component pairs for both, so six vpdpwssd chains run side by side. The
// accumulators are named variables, not arrays: with arrays GCC 12 copied
// each one to another register and back around every vpdpwssd, which put
// two moves on each chain and made the loop wait on it (perf annotate,
// stop 44).
template <typename W>
RELIGHT_TARGET_AVX512_VNNI inline void TwoFullTiles(const W* tile, uint32_t components,
                                                    const int32_t (*k)[kMaxCompressedComponents / 2 + 1],
                                                    const __m512i* half, const ChannelFinish* finish,
                                                    int32_t* out) {
  const uint32_t pairs = components / 2;
  const W* second = tile + 16 * components;
  __m512i a0 = half[0], a1 = half[1], a2 = half[2];
  __m512i b0 = half[0], b1 = half[1], b2 = half[2];
  for (uint32_t p = 0; p < pairs; ++p)
    PairStep(LoadPairs(tile + 32 * p), LoadPairs(second + 32 * p), k, p, a0, a1, a2, b0, b1, b2);
  if (components % 2 != 0)
    PairStep(LoadLast(tile + 32 * pairs), LoadLast(second + 32 * pairs), k, pairs, a0, a1, a2, b0, b1, b2);
  StoreRgb16(Finish(a0, finish[0]), Finish(a1, finish[1]), Finish(a2, finish[2]), out);
  StoreRgb16(Finish(b0, finish[0]), Finish(b1, finish[1]), Finish(b2, finish[2]), out + 48);
}

// Every shift, negative ones included (the 256-bit bodies leave those to the
// scalar path).
template <typename W>
RELIGHT_TARGET_AVX512_VNNI void ClusterAvx512Vnni(const W* w, uint32_t n, uint32_t components,
                                                 const PackedClusterMultipliers& m, int32_t* out) {
  // The multipliers are broadcast from the packed int32 where vpdpwssd
  // needs them (a vpbroadcastd load), not first written out as 64-byte vectors.
  const int32_t(*k)[kMaxCompressedComponents / 2 + 1] = m.packed;
  __m512i half[3];
  ChannelFinish finish[3];
  for (int ch = 0; ch < 3; ++ch) {
    const int s = m.shift[ch];
    half[ch] = _mm512_set1_epi32(s > 0 ? int32_t{1} << (s - 1) : 0);
    finish[ch].mean = _mm512_set1_epi32(m.mean[ch]);
    finish[ch].mean64 = _mm512_set1_epi64(m.mean[ch]);
    finish[ch].left = s < 0;
    finish[ch].shift = _mm_cvtsi32_si128(s < 0 ? -s : s);
  }
  uint32_t i0 = 0;
  // Two full tiles a step: six independent vpdpwssd chains.
  for (; i0 + 32 <= n; i0 += 32)
    TwoFullTiles(w + size_t{i0} * components, components, k, half, finish, out + size_t{i0} * 3);
  // The rest one tile at a time: a full one, then a short last one.
  for (; i0 < n; i0 += 16) {
    const uint32_t count = n - i0 < 16 ? n - i0 : 16;
    __m512i a[3] = {half[0], half[1], half[2]};
    AccumulateTile(w + size_t{i0} * components, count, components, k, a);
    for (int ch = 0; ch < 3; ++ch) a[ch] = Finish(a[ch], finish[ch]);
    StoreRgb(a, count, out + size_t{i0} * 3);
  }
}

inline PackedClusterMultipliers Packed(const ClusterMultipliers& m, uint32_t components) {
  PackedClusterMultipliers p;
  PairMultipliers(m, components, p.packed);
  for (int ch = 0; ch < 3; ++ch) {
    p.mean[ch] = m.mean[ch];
    p.shift[ch] = m.shift[ch];
  }
  return p;
}

template <typename W>
RELIGHT_TARGET_AVX_VNNI void ClusterAvxVnni(const W* w, uint32_t n, uint32_t components,
                                            const ClusterMultipliers& m, int32_t* out) {
  const uint32_t pairs = components / 2;
  int32_t packed[3][kMaxCompressedComponents / 2 + 1];
  PairMultipliers(m, components, packed);
  __m256i k[3][kMaxCompressedComponents / 2 + 1];
  for (int ch = 0; ch < 3; ++ch) {
    for (uint32_t p = 0; p < (components + 1) / 2; ++p) k[ch][p] = _mm256_set1_epi32(packed[ch][p]);
  }
  __m256i half[3], mean[3];
  __m128i shift[3];
  for (int ch = 0; ch < 3; ++ch) {
    const int s = m.shift[ch];
    half[ch] = _mm256_set1_epi32(s > 0 ? int32_t{1} << (s - 1) : 0);
    mean[ch] = _mm256_set1_epi32(m.mean[ch]);
    shift[ch] = _mm_cvtsi32_si128(s);
  }
  const uint32_t tiles = n / 16;  // full tiles; the caller does the short last one
  for (uint32_t b = 0; b < tiles; ++b) {
    const uint32_t i0 = 16 * b;
    const W* tile = w + size_t{i0} * components;
    __m256i lo[3], hi[3];  // receivers i0 + 0..7, i0 + 8..15
    for (int ch = 0; ch < 3; ++ch) lo[ch] = hi[ch] = half[ch];
    for (uint32_t p = 0; p < pairs; ++p) {
      const __m256i a = cpca_simd::LoadPairs256(tile + 32 * p);
      const __m256i c = cpca_simd::LoadPairs256(tile + 32 * p + 16);
      for (int ch = 0; ch < 3; ++ch) {
        lo[ch] = _mm256_dpwssd_avx_epi32(lo[ch], a, k[ch][p]);
        hi[ch] = _mm256_dpwssd_avx_epi32(hi[ch], c, k[ch][p]);
      }
    }
    if (components % 2 != 0) {
      const W* last = tile + 32 * pairs;
      const __m256i a = cpca_simd::LoadLast256(last);
      const __m256i c = cpca_simd::LoadLast256(last + 8);
      for (int ch = 0; ch < 3; ++ch) {
        lo[ch] = _mm256_dpwssd_avx_epi32(lo[ch], a, k[ch][pairs]);
        hi[ch] = _mm256_dpwssd_avx_epi32(hi[ch], c, k[ch][pairs]);
      }
    }
    __m256i first[3], second[3];
    for (int ch = 0; ch < 3; ++ch) {
      first[ch] = _mm256_add_epi32(mean[ch], _mm256_sra_epi32(lo[ch], shift[ch]));
      second[ch] = _mm256_add_epi32(mean[ch], _mm256_sra_epi32(hi[ch], shift[ch]));
    }
    cpca_simd::StoreInterleaved(first[0], first[1], first[2], out + size_t{i0} * 3);
    cpca_simd::StoreInterleaved(second[0], second[1], second[2], out + size_t{i0} * 3 + 24);
  }
}

}  // namespace

void CompressedClusterAvx512VnniQ12(const int16_t* w, uint32_t n, uint32_t components, const ClusterMultipliers& m,
                                    int32_t* out) {
  ClusterAvx512Vnni(w, n, components, Packed(m, components), out);
}
void CompressedClusterAvx512VnniQ12(const int8_t* w, uint32_t n, uint32_t components, const ClusterMultipliers& m,
                                    int32_t* out) {
  ClusterAvx512Vnni(w, n, components, Packed(m, components), out);
}
void CompressedClusterPackedAvx512VnniQ12(const int16_t* w, uint32_t n, uint32_t components,
                                          const PackedClusterMultipliers& m, int32_t* out) {
  ClusterAvx512Vnni(w, n, components, m, out);
}
void CompressedClusterPackedAvx512VnniQ12(const int8_t* w, uint32_t n, uint32_t components,
                                          const PackedClusterMultipliers& m, int32_t* out) {
  ClusterAvx512Vnni(w, n, components, m, out);
}
void CompressedClusterAvxVnniQ12(const int16_t* w, uint32_t n, uint32_t components, const ClusterMultipliers& m,
                                 int32_t* out) {
  ClusterAvxVnni(w, n, components, m, out);
}
void CompressedClusterAvxVnniQ12(const int8_t* w, uint32_t n, uint32_t components, const ClusterMultipliers& m,
                                 int32_t* out) {
  ClusterAvxVnni(w, n, components, m, out);
}

}  // namespace relight

#else  // no x86-64 vector path on this target: CompressedClusterQ12 stays scalar

namespace relight {
void CompressedClusterAvx512VnniQ12(const int16_t*, uint32_t, uint32_t, const ClusterMultipliers&, int32_t*) {}
void CompressedClusterPackedAvx512VnniQ12(const int16_t*, uint32_t, uint32_t, const PackedClusterMultipliers&,
                                          int32_t*) {}
void CompressedClusterPackedAvx512VnniQ12(const int8_t*, uint32_t, uint32_t, const PackedClusterMultipliers&,
                                          int32_t*) {}
void CompressedClusterAvx512VnniQ12(const int8_t*, uint32_t, uint32_t, const ClusterMultipliers&, int32_t*) {}
void CompressedClusterAvxVnniQ12(const int16_t*, uint32_t, uint32_t, const ClusterMultipliers&, int32_t*) {}
void CompressedClusterAvxVnniQ12(const int8_t*, uint32_t, uint32_t, const ClusterMultipliers&, int32_t*) {}
}  // namespace relight

#endif
