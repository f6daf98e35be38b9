// Emitters on the grids (emitter_grids.h).
//
// Scaling and overflow of OnSolved: f UQ0.32 x B Q32 (int64) summed over a
// point's links in Int128; ValidateBake bounds each point's factor sum by
// 2 (bake_check_grid_links.cc), so |sum| < 2^33 x 2^63 = 2^96. Rounded to
// Q32 lux per lm/m^2 in int64 (saturating), then x pi (Q29) in Int128
// (< 2^63 x 2^31) to Q24 lux per cd/m^2, saturated to int32 (a unit
// response past 128 lux per cd/m^2 would need a reflectance near 1).
// AddTo: unit Q24 (< 2^31) x luminance LightQ12 (< 2^31) in int64, rounded
// to LightQ12 and added with int32 saturation, as the vertices (surface_emitters.cc).
#include "emitter_grids.h"

#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

// pi in Q29: unit luminance L = 1 cd/m^2 emits M = pi L lm/m^2.
constexpr int64_t kPiQ29 = 1686629713;

}  // namespace

void EmitterGrids::Open(const Bake& bake) {
  h_ = bake.hierarchy ? &*bake.hierarchy : nullptr;
  active_ = h_ != nullptr && h_->has_grid_links() && !bake.grids.empty();
  grid_first_.clear();
  uint32_t points = 0;
  for (const BakeGrid& grid : bake.grids) {
    grid_first_.push_back(points);
    points += grid.point_count();
  }
  for (std::vector<int32_t>& s : slots_) s.assign(active_ ? size_t{points} * 3 : 0, 0);
}

void EmitterGrids::OnSolved(int slot, const int64_t* exitance_q32) {
  if (!active_) return;
  int32_t* out = slots_[slot].data();
  const size_t points = h_->grid_link_offsets.size() - 1;
  for (size_t p = 0; p < points; ++p) {
    Int128 a0 = 0, a1 = 0, a2 = 0;
    for (uint32_t e = h_->grid_link_offsets[p]; e < h_->grid_link_offsets[p + 1]; ++e) {
      const int64_t* b = &exitance_q32[3 * size_t{h_->grid_link_node[e]}];
      const Int128 f = h_->grid_link_f[e];
      a0 += f * b[0];
      a1 += f * b[1];
      a2 += f * b[2];
    }
    const Int128 sums[3] = {a0, a1, a2};
    for (int c = 0; c < 3; ++c) {
      const int64_t lux_q32 = RoundShiftSat64(sums[c], -32);
      out[3 * p + c] = SaturateI32(RoundShift(static_cast<Int128>(lux_q32) * kPiQ29, 32 + 29 - 24));
    }
  }
}

void EmitterGrids::AddTo(const SurfaceEmitters& emitters,
                         std::vector<std::vector<int32_t>>* grid_q12) const {
  if (!active_) return;
  for (int slot = 0; slot < kMaxSurfaceEmitters; ++slot) {
    const int32_t* lum = emitters.solved_luminance_q12(slot);
    if (lum == nullptr || (lum[0] == 0 && lum[1] == 0 && lum[2] == 0)) continue;
    const int32_t* unit = slots_[slot].data();
    for (size_t g = 0; g < grid_q12->size(); ++g) {
      std::vector<int32_t>& grid = (*grid_q12)[g];
      const int32_t* u = unit + 3 * size_t{grid_first_[g]};
      for (size_t i = 0; i < grid.size(); ++i) {
        const int64_t add = (int64_t{u[i]} * lum[i % 3] + (int64_t{1} << 23)) >> 24;
        grid[i] = SaturateI32(int64_t{grid[i]} + add);
      }
    }
  }
}

}  // namespace relight
