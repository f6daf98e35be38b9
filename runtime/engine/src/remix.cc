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

namespace {

// [first, first + count) of n receivers: slice `part` of `parts`.
void Slice(uint32_t n, uint32_t part, uint32_t parts, uint32_t* first, uint32_t* count) {
  const uint64_t a = static_cast<uint64_t>(n) * part / parts;
  const uint64_t b = static_cast<uint64_t>(n) * (part + 1) / parts;
  *first = static_cast<uint32_t>(a);
  *count = static_cast<uint32_t>(b - a);
}

}  // namespace

void RemixQ12(const Bake& bake, const std::vector<LuminaireRuntime>& lums, MixSource* mix,
              int64_t* scratch, uint32_t scratch_len, EngineOutputs* out) {
  RemixSliceQ12(bake, lums, 0, 1, mix, scratch, scratch_len, out);
}

void RemixSliceQ12(const Bake& bake, const std::vector<LuminaireRuntime>& lums, uint32_t part,
                   uint32_t parts, MixSource* mix, int64_t* scratch, uint32_t scratch_len,
                   EngineOutputs* out) {
  const uint32_t n = static_cast<uint32_t>(lums.size());
  uint32_t first = 0, count = 0;
  Slice(bake.mesh.vertex_count(), part, parts, &first, &count);
  size_t at = static_cast<size_t>(first) * 3;
  for (uint32_t i = 0; i < n; ++i) {
    SetGains(lums[i].state, &mix[i]);
    mix[i].a = lums[i].sets[0].light.data() + at;
    mix[i].b = nullptr;
  }
  MixLuminairesQ12(mix, n, count, scratch, scratch_len, out->vertex.data() + at);
  for (uint32_t g = 0; g < out->grid_total.size(); ++g) {
    Slice(bake.grids[g].point_count(), part, parts, &first, &count);
    at = static_cast<size_t>(first) * 3;
    for (uint32_t i = 0; i < n; ++i) {
      const SetCache& cache = lums[i].sets[g + 1];
      mix[i].a = cache.light.data() + at;
      mix[i].b = cache.direct.empty() ? nullptr : cache.direct.data() + at;
    }
    MixLuminairesQ12(mix, n, count, scratch, scratch_len, out->grid_total[g].data() + at);
    // Direct only: the exact-direct luminaires, packed to the front.
    uint32_t direct_sources = 0;
    for (uint32_t i = 0; i < n; ++i) {
      const SetCache& cache = lums[i].sets[g + 1];
      if (cache.direct.empty()) continue;
      MixSource& m = mix[direct_sources++];
      SetGains(lums[i].state, &m);
      m.a = cache.direct.data() + at;
      m.b = nullptr;
    }
    MixLuminairesQ12(mix, direct_sources, count, scratch, scratch_len, out->grid_direct[g].data() + at);
  }
}

}  // namespace relight
