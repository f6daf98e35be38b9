// The AVX2 body of CompressedClusterQ12 (compressed_recombine.h), apart
// because the rest of the runtime is built with -mgeneral-regs-only.
// Integer instructions only; bit-identical to CompressedClusterScalarQ12.
#pragma once

#include <cstdint>

#include "compressed_recombine.h"

namespace relight {

// Receivers [0, n - n % 16) of the cluster (the caller does the tail on the
// scalar path); same arguments and results as CompressedClusterScalarQ12,
// at every shift (a negative one finishes in int64 lanes and saturates, as
// the scalar path).
// Per 16-receiver tile (compressed_tiles.h) and component pair: two loads
// that are already the int16 pairs of receivers 0..7 and 8..15, and per
// channel two _mm256_madd_epi16 into exact int32 sums (see the scaling
// comment there); then shift (or scale up), mean, and a 3-way interleave.
void CompressedClusterAvx2Q12(const int16_t* w, uint32_t n, uint32_t components,
                              const ClusterMultipliers& m, int32_t* out);
// The same over 8-bit weights (sign-extended to the same int16 pairs).
void CompressedClusterAvx2Q12(const int8_t* w, uint32_t n, uint32_t components,
                              const ClusterMultipliers& m, int32_t* out);

}  // namespace relight
