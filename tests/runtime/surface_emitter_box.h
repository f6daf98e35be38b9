// The closed box (1 m, 6.25 cm patches, reflectance 0.7 / 0.6 / 0.5,
// hierarchical) that the incremental and later-bounce emitter tests share,
// baked once per test binary, and two helpers of theirs.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "relight/baker/baker.h"
#include "relight/engine/engine.h"
#include "test_scenes.h"

namespace relight::testing {

inline const Bake& EmitterBoxBake() {
  static const Bake bake = [] {
    baker::BakeOptions options;
    options.solver = baker::SolverKind::kHierarchical;
    return baker::Baker(baker::test_scenes::ClosedBox(0.0625, {0.7, 0.6, 0.5}), options).Bake();
  }();
  return bake;
}

// cd/m^2 as LightQ12.
inline LightQ12 Light(double cd_m2) { return LightQ12::FromRaw(static_cast<int32_t>(std::lround(cd_m2 * 4096))); }

inline std::vector<int32_t> Luminance(const Engine& engine) {
  return std::vector<int32_t>(engine.vertex_luminance().begin(), engine.vertex_luminance().end());
}

}  // namespace relight::testing
