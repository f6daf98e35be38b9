// Run-time emitter slots (surface_emitters.h).
//
// Scaling and overflow of AddTo: unit response Q24 (< 2^31) x luminance
// LightQ12 (< 2^31) in int64 (< 2^62), rounded to LightQ12 and added with
// int32 saturation.
#include "surface_emitters.h"

#include <utility>

#include "relight/base/fixed_ops.h"
#include "surface_emitter_coverage.h"
#include "surface_emitter_vertices.h"

namespace relight {
namespace {

Status NoHierarchy() {
  return Status(StatusCode::kUnsupported,
                "surface emitter: the bake has no radiosity hierarchy (bake it with "
                "--solver hierarchical and without --no-hierarchy)");
}

}  // namespace

Status SurfaceEmitters::Open(const Bake& bake) {
  bake_ = &bake;
  vertex_count_ = bake.mesh.vertex_count();
  supported_ = bake.hierarchy.has_value();
  if (!supported_) return Status::Ok();
  // The hierarchy's indices were checked by the engine's ValidateBake.
  RELIGHT_RETURN_IF_ERROR(solver_.Init(bake));
  const BakeHierarchy& h = *bake.hierarchy;
  surface_root_.assign(bake.mesh.surface_names.size(), kBakeNoIndex);
  for (uint32_t k = 0; k < h.node_count(); ++k) {
    if (h.node_parent[k] == kBakeNoIndex && h.node_surface[k] < surface_root_.size())
      surface_root_[h.node_surface[k]] = k;
  }
  vertex_area_.assign(vertex_count_, 0);
  VertexLeafAreas(h, vertex_count_, vertex_area_.data());
  vertex_sum_.assign(size_t{vertex_count_} * 3, 0);
  coverage_scratch_.assign(h.node_count(), 0);
  exitance_.assign(size_t{h.node_count()} * 3, 0);
  for (Slot& s : slots_) {
    s.coverage_q32.assign(h.node_count(), 0);
    s.unit_q24.assign(size_t{vertex_count_} * 3, 0);
  }
  return Status::Ok();
}

Status SurfaceEmitters::CheckSlot(int slot) const {
  if (!supported_) return NoHierarchy();
  if (slot < 0 || slot >= kMaxSurfaceEmitters) {
    return Status(StatusCode::kInvalidArgument,
                  StrFormat("surface emitter: slot %d outside 0..%d", slot, kMaxSurfaceEmitters - 1));
  }
  return Status::Ok();
}

Status SurfaceEmitters::Place(int slot, const SurfaceEmitterShape& shape) {
  RELIGHT_RETURN_IF_ERROR(CheckSlot(slot));
  const std::vector<std::string>& names = bake_->mesh.surface_names;
  uint32_t surface = 0;
  while (surface < names.size() && names[surface] != shape.surface) ++surface;
  if (surface == names.size() || surface_root_[surface] == kBakeNoIndex) {
    return Status(StatusCode::kNotFound,
                  StrFormat("surface emitter: no surface '%s' in the bake", shape.surface.c_str()));
  }
  for (int64_t& f : coverage_scratch_) f = 0;
  const Status st = SurfaceEmitterCoverageQ32(*bake_->hierarchy, bake_->mesh, surface_root_[surface],
                                              shape.corners_q16, shape.corner_count,
                                              coverage_scratch_.data());
  if (!st.ok()) {
    return Status(st.code(), StrFormat("%s (surface '%s')", st.message().c_str(), shape.surface.c_str()));
  }
  Slot& s = slots_[slot];
  s.coverage_q32.swap(coverage_scratch_);
  s.placed = true;
  s.dirty = true;
  return Status::Ok();
}

Status SurfaceEmitters::SetLuminance(int slot, const LightQ12 rgb[3]) {
  RELIGHT_RETURN_IF_ERROR(CheckSlot(slot));
  for (int c = 0; c < 3; ++c) {
    if (rgb[c].raw() < 0) return Status(StatusCode::kInvalidArgument, "surface emitter: luminance < 0");
  }
  for (int c = 0; c < 3; ++c) slots_[slot].luminance_q12[c] = rgb[c].raw();
  return Status::Ok();
}

Status SurfaceEmitters::Remove(int slot) {
  RELIGHT_RETURN_IF_ERROR(CheckSlot(slot));
  slots_[slot].placed = false;
  slots_[slot].dirty = false;
  return Status::Ok();
}

int SurfaceEmitters::SolvePending() {
  int solved = 0;
  last_sweeps_ = 0;
  for (int slot = 0; slot < kMaxSurfaceEmitters; ++slot) {
    Slot& s = slots_[slot];
    if (!s.placed || !s.dirty) continue;
    last_sweeps_ += solver_.SolveRgb(s.coverage_q32.data(), exitance_.data());
    if (observer_ != nullptr) observer_->OnSolved(slot, exitance_.data());
    // Unit luminance L = 1 cd/m^2 emits M = pi L; the vertex luminance is
    // exitance / pi, so the pi cancels: the unit-coverage solve is the answer.
    LeavesToVerticesQ24(*bake_->hierarchy, vertex_area_.data(), vertex_count_, exitance_.data(),
                        vertex_sum_.data(), s.unit_q24.data());
    s.dirty = false;
    ++solved;
  }
  return solved;
}

void SurfaceEmitters::AddTo(int32_t* vertex_q12) const {
  for (const Slot& s : slots_) {
    if (!s.placed || s.dirty) continue;
    if (s.luminance_q12[0] == 0 && s.luminance_q12[1] == 0 && s.luminance_q12[2] == 0) continue;
    const size_t n = size_t{vertex_count_} * 3;
    for (size_t i = 0; i < n; ++i) {
      const int64_t add = (int64_t{s.unit_q24[i]} * s.luminance_q12[i % 3] + (int64_t{1} << 23)) >> 24;
      vertex_q12[i] = SaturateI32(int64_t{vertex_q12[i]} + add);
    }
  }
}

}  // namespace relight
