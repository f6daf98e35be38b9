// Recombination of a compressed basis (bake.h BakeCompressedBasis, clustered
// PCA after Sloan et al. 2003) without expanding it. Dobashi Eq. 18 over the
// cluster form: per look (an aim or LID change)
//   1. project the look onto every cluster's mean and components: the
//      vectors are a small term-major basis of C (r + 1) "receivers", so this
//      is RecombineQ12 (recombine.h) with the usual per-term multipliers
//      (weights.h): the value in LightQ12 of each vector at this look;
//   2. per cluster and channel, turn the r component values into int16
//      multipliers K_j and one shift s (ClusterMultipliersQ12; on AVX-512
//      the same integers in vectors, compressed_multipliers_avx512.h);
//   3. per receiver, a dot product of length r: out = mean + (sum_j q_j K_j) >> s.
// Cost ∝ C (r + 1) (N+1)^2 + receivers x r, not receivers x (N+1)^2.
// Integer-only, allocation-free (caller-owned spans), thread-safe.
#pragma once

#include <cstdint>

#include "relight/bake/bake.h"

namespace relight {

// One cluster's multipliers for one look: k[ch * r + j] (int16), mean[ch]
// (LightQ12, clamped to +-(2^30 - 1)), shift[ch] in [-31, 31].
struct ClusterMultipliers {
  int16_t k[3 * kMaxCompressedComponents];
  int32_t mean[3];
  int shift[3];
};

// The largest |K| for r components and weights of at most weight_one
// (bake.h CompressedWeightOne): r x weight_one x K_max < 2^30, and
// K_max <= kCompressedWeightOne (an int16 that madd can pair).
int32_t CompressedMultiplierLimit(uint32_t components, int32_t weight_one = kCompressedWeightOne);

// From the projected values of cluster c (projection + c (r + 1) * 3: the
// mean, then component j at (1 + j) * 3 + ch; LightQ12 for a weight of 1,
// i.e. q = weight_one, 16383 or 127):
//   K_j = round(P_j 2^s / weight_one), halves away from zero, with
//   s the largest in [-31, 31] that keeps every |K_j| <= CompressedMultiplierLimit(r, weight_one).
//   s < 0 only for a component worth more than limit x weight_one LightQ12
//   at its largest weight: 16384 cd/m^2 at r = 16 with 16-bit weights (a
//   bright beam in an all-in-SH basis), 508 cd/m^2 with 8-bit ones (their
//   multipliers meet the int16 cap first). The AVX-512 body finishes those
//   in int64; the 256-bit paths leave them to the scalar one.
void ClusterMultipliersQ12(const int32_t* projection, uint32_t components, int32_t weight_one,
                           ClusterMultipliers* m);
// The shift ClusterMultipliersQ12 gives a channel whose largest |P_j| is
// `largest` (0 <= largest <= 2^31), and the mean it keeps (the projected
// mean clamped to +-(2^30 - 1)).
int ClusterShiftQ12(int64_t largest, uint32_t components, int32_t weight_one);
int32_t ClusterMeanQ12(int32_t projected_mean);

// Receivers [0, n) of one cluster, weights in tiles (compressed_tiles.h;
// w_ij below is w[TiledWeightOffset(n, r, i, j)]):
//   out[i * 3 + ch] = mean[ch] + ((sum_j w_ij K[ch r + j] + half) >> shift[ch])
// (for shift < 0: mean + sum x 2^-shift in int64, saturated to int32).
// Scaling and overflow:
//   w      int16 in [-16383, 16383] (< 2^14), or int8 in [-127, 127] for an
//          8-bit basis (the same formula; the bake checks both)
//   K      int16, |K| <= CompressedMultiplierLimit(r)
//   acc    int32, exact: |acc| <= r x weight_one x K_max < 2^30, so acc + half
//          (half = 2^(s-1) <= 2^30) cannot overflow; the shift rounds halves up
//   out    LightQ12: for shift >= 0, |mean| < 2^30 plus a shifted sum of at
//          most 2^30 in magnitude: inside int32, never saturates; for
//          shift < 0 (|v| < 2^62 in int64) saturated to int32.
// The scalar, AVX2 (compressed_recombine_avx2.h) and VNNI
// (compressed_recombine_vnni.h) paths compute these same integers: bit-identical.
void CompressedClusterScalarQ12(const int16_t* w, uint32_t n, uint32_t components,
                                const ClusterMultipliers& m, int32_t* out);
void CompressedClusterScalarQ12(const int8_t* w, uint32_t n, uint32_t components,
                                const ClusterMultipliers& m, int32_t* out);
// Receivers [from, n) of the same cluster (n and the tiles as above).
void CompressedClusterTailQ12(const int16_t* w, uint32_t from, uint32_t n, uint32_t components,
                              const ClusterMultipliers& m, int32_t* out);
void CompressedClusterTailQ12(const int8_t* w, uint32_t from, uint32_t n, uint32_t components,
                              const ClusterMultipliers& m, int32_t* out);
// Same, on the active vector path (recombine_dispatch.h): AVX-512 VNNI or
// AVX2 at every shift, AVX-VNNI when every shift is >= 0 (else AVX2).
void CompressedClusterQ12(const int16_t* w, uint32_t n, uint32_t components,
                          const ClusterMultipliers& m, int32_t* out);
void CompressedClusterQ12(const int8_t* w, uint32_t n, uint32_t components,
                          const ClusterMultipliers& m, int32_t* out);

// int32 values of the projection scratch a compressed basis needs: 3 C (r + 1).
uint64_t CompressedProjectionValues(const BakeCompressedBasis& cpca);

// Steps 1-3 for one luminaire on one receiver set: coef_q16 its per-term
// coefficients (weights.h TermCoefficientsQ16), `terms` of them; k_terms
// (3 x terms), scratch (>= 3 int64) and projection
// (CompressedProjectionValues) caller-owned; out: 3 per receiver, LightQ12.
// The weights must be tiled (TileCompressedWeights: the engine does it at
// Open). Returns the terms the projection accumulated.
uint32_t RecombineCompressedQ12(const BakeCompressedBasis& cpca, int terms, const int64_t* coef_q16,
                                int32_t* k_terms, int64_t* scratch, uint32_t scratch_len,
                                int32_t* projection, int32_t* out);

}  // namespace relight
