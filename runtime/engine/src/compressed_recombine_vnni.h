// The VNNI bodies of CompressedClusterQ12 (compressed_recombine.h), apart
// because the rest of the runtime is built with -mgeneral-regs-only.
// Integer instructions only; bit-identical to CompressedClusterScalarQ12.
//
// vpdpwssd (no "s": not the saturating form) is vpmaddwd + vpaddd in one
// instruction: acc + w_a K_a + w_b K_b with the int32 add wrapping exactly as
// vpaddd does. The bounds of compressed_recombine.h keep every partial sum
// inside int32 (|acc| <= r x 16383 x K_max < 2^30; the accumulators start at
// the rounding half <= 2^30, so |half + acc| < 2^31), so nothing wraps and the
// sums are the scalar path's.
#pragma once

#include <cstdint>

#include "compressed_recombine.h"

namespace relight {

// AVX-512 (F, BW, VL, VNNI), two 16-receiver tiles (compressed_tiles.h) a
// step in 512-bit registers; the cluster's short last tile with masked loads
// and stores, so it does receivers [0, n), all of them, at every shift (a
// negative one finishes in int64 and saturates, as the scalar path). Per
// tile and component pair: one load, already the 16 receivers' int16 pairs,
// and three vpdpwssd (one per channel); an odd
// count's last component zero-extended to (w, 0) pairs; then per channel a
// shift and the mean, and 6 vpermt2d interleave R, G, B.
void CompressedClusterAvx512VnniQ12(const int16_t* w, uint32_t n, uint32_t components,
                                    const ClusterMultipliers& m, int32_t* out);

// AVX-VNNI (VEX, 256 bits): the AVX2 body (compressed_recombine_avx2.h) with
// each vpmaddwd + vpaddd fused into one vpdpwssd. Receivers
// [0, n - n % 16) (the full tiles), shifts >= 0 only; the caller does the tail.
void CompressedClusterAvxVnniQ12(const int16_t* w, uint32_t n, uint32_t components,
                                 const ClusterMultipliers& m, int32_t* out);
// One cluster's multipliers in the form the AVX-512 body takes: per channel
// the pairs (K_2p, K_2p+1) packed as compressed_recombine_interleave.h's
// PackPair (an odd r's last K paired with 0), the mean and the shift: what
// PairMultipliers makes of a ClusterMultipliers (compressed_multipliers_avx512.h
// makes it straight from the projection).
struct PackedClusterMultipliers {
  int32_t packed[3][kMaxCompressedComponents / 2 + 1];
  int32_t mean[3];
  int shift[3];
};

// CompressedClusterAvx512VnniQ12 from packed multipliers.
void CompressedClusterPackedAvx512VnniQ12(const int16_t* w, uint32_t n, uint32_t components,
                                          const PackedClusterMultipliers& m, int32_t* out);
void CompressedClusterPackedAvx512VnniQ12(const int8_t* w, uint32_t n, uint32_t components,
                                          const PackedClusterMultipliers& m, int32_t* out);

// Both bodies also over 8-bit weights: a sign-extending load in front of the
// same vpdpwssd (the int16 pairs are the same values).
void CompressedClusterAvx512VnniQ12(const int8_t* w, uint32_t n, uint32_t components,
                                    const ClusterMultipliers& m, int32_t* out);
void CompressedClusterAvxVnniQ12(const int8_t* w, uint32_t n, uint32_t components,
                                 const ClusterMultipliers& m, int32_t* out);

}  // namespace relight
