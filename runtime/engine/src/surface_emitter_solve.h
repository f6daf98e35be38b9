// Hierarchical radiosity from the bake's stored quadtrees and links, in fixed
// point, for run-time emitters: Gauss-Seidel sweeps over the surfaces exactly
// as the baker's solver (baker/src/hierarchy_solve.h, docs/hierarchy.md):
// per surface every node gathers sum (f + g.(x - c)) B over its links, the
// irradiance is pushed down (a leaf takes the linear field at its centroid),
// leaves take M = S + rho E, exitance is pulled up area-weighted. The three
// channels (reflectance differs per channel) go through each sweep together,
// so every link is read once per sweep.
//
// Init() allocates everything (gather lists, frames, weights, scratch);
// Solve() is integer-only and allocates nothing. Not thread-safe (scratch).
#pragma once

#include <cstdint>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/base/status.h"

namespace relight {

// Exitance and emission per node: Q32 (2^32 = 1 lm/m^2, or 1 per unit of
// whatever the emission is measured in: the solve is linear).
inline constexpr int kExitanceFracBits = 32;
// Sweeps stop when the estimated remaining change (last change x r / (1 - r),
// r the observed contraction, at most 0.99) is below 2^-17 (7.6e-6) of the
// largest leaf exitance, or after this many sweeps.
inline constexpr int kEmitterSolveMaxSweeps = 200;
inline constexpr int kEmitterSolveToleranceLog2 = 17;

class HierarchySolveQ32 {
 public:
  // Needs bake.hierarchy (kUnsupported without); the bake must outlive this.
  Status Init(const Bake& bake);
  // exitance_q32[3 k + c] for every node k and channel c from emitted_q32[k]
  // (the same in every channel; leaves only, inner nodes ignored). Returns
  // the sweeps it took. first_shot_q32 (optional, per node, leaves only):
  // irradiance (Q32 lux per unit) the leaves receive besides what they
  // gather, e.g. adaptive refine's direct light from an emitter whose own
  // exitance is then left out of emitted_q32; peak_floor_q32: the stopping
  // rule's peak exitance is at least this (that emitter's own exitance, so
  // the solve stops where it would with the emitter in emitted_q32).
  int SolveRgb(const int64_t* emitted_q32, int64_t* exitance_q32, const int64_t* first_shot_q32 = nullptr,
               int64_t peak_floor_q32 = 0);
  uint32_t node_count() const { return static_cast<uint32_t>(child_weight_q32_.size()); }

 private:
  void Pull(uint32_t begin, uint32_t end, int64_t* b) const;

  const BakeHierarchy* h_ = nullptr;
  // Node k gathers from gather_source_[e] with factor gather_f_[e] (UQ0.32)
  // and gradient gather_g_[2e..2e+1] (Q8.23 per metre), e in
  // [gather_offsets_[k], gather_offsets_[k + 1]).
  std::vector<uint32_t> gather_offsets_, gather_source_, gather_f_;
  std::vector<int32_t> gather_g_;
  std::vector<uint64_t> child_weight_q32_;  // area over the parent's, 2^32 = all
  std::vector<int32_t> centre_uv_q16_;      // 2 per node, surface frame, m
  std::vector<uint64_t> rho_q32_;           // 3 per node (leaves), 2^32 = 1
  std::vector<uint32_t> run_begin_;         // first node of each tree, then node_count
  std::vector<int64_t> g0_, gu_, gv_;       // gathered a + b u + c v, Q32, 3 per node
};

}  // namespace relight
