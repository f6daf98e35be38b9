// ClusterMultipliersQ12 (compressed_recombine.h) in AVX-512 vectors, straight
// into the packed form the AVX-512 kernel takes (compressed_recombine_vnni.h):
// per aim change every cluster of every compressed basis needs 3 r of these
// multipliers, and the scalar loop over them was 6 % of a stage update
// (docs/performance.md, stop 44). Apart because the rest of the runtime is
// built with -mgeneral-regs-only; integer instructions only.
//
// The same integers as PairMultipliers of ClusterMultipliersQ12:
//   mean[ch] = the projected mean clamped to +-(2^30 - 1);
//   shift[ch] = ClusterShiftQ12 of the channel's largest |P_j| (scalar);
//   K_j = min(floor((|P_j| 2^s + one / 2) / one), limit) with P_j's sign,
// the division as a multiply by ceil(2^q / one) and a right shift by q
// (q = 38 for one = 127, 45 for 16383), exact for every dividend below
// 4 x 2^29 (see the .cc). A dividend here is below (limit + 1) x one < 2^28
// plus one / 2 whenever the shift is >= 0, since the shift keeps the
// channel's largest value within the limit.
#pragma once

#include <cstdint>

#include "compressed_recombine_vnni.h"

namespace relight {

// False (m unspecified) when a channel's shift is negative (a bright
// cluster, which the scalar path handles) or weight_one is not 127 or 16383.
bool ClusterMultipliersAvx512(const int32_t* projection, uint32_t components, int32_t weight_one,
                              PackedClusterMultipliers* m);

}  // namespace relight
