// The per-luminaire cache: a luminaire whose aim or LID changed is rebuilt
// here, at dimmer 1 and white, for every receiver set (vertices, grids):
// aim -> per-term coefficients (Dobashi Eq. 10, 18, or the LID's own SH
// coefficients rotated, Eq. 22-23) -> recombination (recombine.h) + the
// exact direct term (direct.h). Dimmer and colour are applied later, by the
// remix (remix.h). Integer-only, allocation-free.
#pragma once

#include "luminaire.h"
#include "relight/bake/bake.h"

namespace relight {

// Rebuilds lum's caches (`b` is its bake entry) with `work`'s scratch;
// returns the SH term passes it made (terms x receiver sets recombined).
int RecomputeLuminaireCacheQ12(const Bake& bake, const BakeLuminaire& b, CacheWorkspace* work,
                               LuminaireRuntime* lum);

}  // namespace relight
