// The remix (see remix.h).
#include "remix.h"

#include <cstddef>

namespace relight {
namespace {

void SetGains(const FixtureState& state, MixSource* m) {
  for (int c = 0; c < 3; ++c) m->gain[c] = GainQ30(state.dimmer, state.rgb[c]);
}

}  // namespace

void SizeOutputs(const Bake& bake, EngineOutputs* out, std::vector<MixSource>* mix) {
  mix->resize(bake.luminaires.size());
  out->vertex.assign(static_cast<size_t>(bake.mesh.vertex_count()) * 3, 0);
  out->grid_total.resize(bake.grids.size());
  out->grid_direct.resize(bake.grids.size());
  for (size_t g = 0; g < bake.grids.size(); ++g) {
    out->grid_total[g].assign(static_cast<size_t>(bake.grids[g].point_count()) * 3, 0);
    out->grid_direct[g].assign(static_cast<size_t>(bake.grids[g].point_count()) * 3, 0);
  }
}

void RemixQ12(const Bake& bake, const std::vector<LuminaireRuntime>& lums, MixSource* mix,
              int64_t* scratch, uint32_t scratch_len, EngineOutputs* out) {
  const uint32_t n = static_cast<uint32_t>(lums.size());
  for (uint32_t i = 0; i < n; ++i) {
    SetGains(lums[i].state, &mix[i]);
    mix[i].a = lums[i].sets[0].light.data();
    mix[i].b = nullptr;
  }
  MixLuminairesQ12(mix, n, bake.mesh.vertex_count(), scratch, scratch_len, out->vertex.data());
  for (uint32_t g = 0; g < out->grid_total.size(); ++g) {
    const uint32_t count = bake.grids[g].point_count();
    for (uint32_t i = 0; i < n; ++i) {
      const SetCache& cache = lums[i].sets[g + 1];
      mix[i].a = cache.light.data();
      mix[i].b = cache.direct.empty() ? nullptr : cache.direct.data();
    }
    MixLuminairesQ12(mix, n, count, scratch, scratch_len, out->grid_total[g].data());
    // Direct only: the exact-direct luminaires, packed to the front.
    uint32_t direct_sources = 0;
    for (uint32_t i = 0; i < n; ++i) {
      const SetCache& cache = lums[i].sets[g + 1];
      if (cache.direct.empty()) continue;
      MixSource& m = mix[direct_sources++];
      SetGains(lums[i].state, &m);
      m.a = cache.direct.data();
      m.b = nullptr;
    }
    MixLuminairesQ12(mix, direct_sources, count, scratch, scratch_len, out->grid_direct[g].data());
  }
}

}  // namespace relight
