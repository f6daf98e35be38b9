// The remix: the luminaires' caches (luminaire_cache.h) weighted by dimmer x
// colour and summed (mix.h) into the engine's outputs, LightQ12:
//   vertices  direct + indirect luminance of every luminaire, cd/m^2;
//   grids     total illuminance, and the exact-direct luminaires' direct
//             part alone (a kAllInSh luminaire has no direct arrays), lux.
// This is all a dimmer or colour change costs. Integer-only, allocation-free.
#pragma once

#include <cstdint>
#include <vector>

#include "luminaire.h"
#include "mix.h"
#include "relight/bake/bake.h"

namespace relight {

// The engine's output buffers, sized at Open.
struct EngineOutputs {
  std::vector<int32_t> vertex;                    // 3 per vertex
  std::vector<std::vector<int32_t>> grid_total;   // per grid, 3 per point
  std::vector<std::vector<int32_t>> grid_direct;  // per grid, 3 per point
};

// Sizes `out` for `bake` (zeroed) and `mix` for its luminaires.
void SizeOutputs(const Bake& bake, EngineOutputs* out, std::vector<MixSource>* mix);

// Rewrites every output from the caches of `lums`. `mix` has one entry per
// luminaire; scratch as MixLuminairesQ12 takes it.
void RemixQ12(const Bake& bake, const std::vector<LuminaireRuntime>& lums, MixSource* mix,
              int64_t* scratch, uint32_t scratch_len, EngineOutputs* out);

// The same for slice `part` of `parts` of every receiver set (receivers
// [n part / parts, n (part + 1) / parts)): each receiver's value depends on
// that receiver alone, so slices run on different threads (each with its
// own mix and scratch) give the outputs of one RemixQ12, bit for bit.
void RemixSliceQ12(const Bake& bake, const std::vector<LuminaireRuntime>& lums, uint32_t part,
                   uint32_t parts, MixSource* mix, int64_t* scratch, uint32_t scratch_len,
                   EngineOutputs* out);

}  // namespace relight
