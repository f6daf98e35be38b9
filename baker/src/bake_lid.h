// A luminaire's photometry and orientation in the bake's formats (bake.h):
// mounting, yaw, roll, console ranges and the LID: the axisymmetric samples
// and, for a photometric file with C planes, its table expanded to the full
// circle in the file's own angles plus its SH coefficients in the fixture
// frame (float64 quadrature at bake time, stored in Q48.16, so the runtime
// only rotates them).
#pragma once

#include "relight/bake/bake.h"
#include "relight/baker/scene.h"

namespace relight::baker {

void FillBakeLuminaireLid(const Luminaire& lum, int sh_degree, int lid_samples,
                          relight::BakeLuminaire* out);

}  // namespace relight::baker
