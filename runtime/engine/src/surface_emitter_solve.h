// Hierarchical radiosity from the bake's stored quadtrees and links, in fixed
// point, for run-time emitters: Gauss-Seidel sweeps over the surfaces exactly
// as the baker's solver (baker/src/hierarchy_solve.h, docs/hierarchy.md):
// per surface every node gathers sum (f + g.(x - c)) B over its links (with
// the source's first moment of exitance where the source is an inner node,
// f (B + (g_rev / f_rev) . m): "Bias and its fix"), the
// irradiance is pushed down (a leaf takes the linear field at its centroid),
// leaves take M = S + rho (E + extra), exitance is pulled up area-weighted.
// The three channels (reflectance differs per channel) go through each sweep
// together, so every link is read once per sweep.
//
// Incremental (issue 15): a solve starts from the exitance it is given (the
// slot's previous solution when an emitter moves), so a change only costs the
// sweeps its difference needs. Gathers are int64 (exitance read as int32 Q24,
// bounded at Init). The surfaces are dealt into kEmitterSolveBlocks fixed
// blocks that sweep in parallel (block Gauss-Seidel: a block sees the others'
// exitance as it was at the start of the sweep), so the result is the same
// whatever the thread count.
//
// Init() allocates everything (gather lists, frames, weights, scratch);
// SolveRgb() is integer-only and allocates nothing. Not thread-safe (scratch).
#pragma once

#include <cstdint>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/base/fixed.h"
#include "relight/base/status.h"
#include "surface_emitter_extrapolate.h"
#include "surface_emitter_gather_avx2.h"
#include "surface_emitter_moments.h"
#include "relight/base/worker_pool.h"

namespace relight {

// Exitance and emission per node: Q32 (2^32 = 1 lm/m^2, or 1 per unit of
// whatever the emission is measured in: the solve is linear).
inline constexpr int kExitanceFracBits = 32;
// Gathers read exitance as int32 with this many fraction bits (Q24).
inline constexpr int kGatherFracBits = 24;
// Sweeps stop when the estimated remaining change (last change x r / (1 - r),
// r the observed contraction, at most 0.99) is below 2^-11 (4.9e-4) of the
// largest leaf exitance, or after this many sweeps; the rest of the series
// is then extrapolated (surface_emitter_extrapolate.h), which keeps the
// grids as accurate as 2^-15 without it did (Cornell ceiling panel, floor
// grid: 0.055 % of peak mean against 0.053 %) in 9 sweeps instead of 13 on
// the paper's room. (2^-15 from issue 15's int64 solve; 2^-17 before.
// At 2^-12 the vertices barely changed -- Cornell box against the float64
// solve 4.7e-4 of peak max, 1.1e-4 mean, against 4.4e-4 and 8.4e-5 at
// 2^-17 -- but the calculation grids, lit mostly by interreflected light,
// came out dark by 0.24 % of peak on average (emitter_grid_test, FE ceiling
// panel; bar 0.2 %); at 2^-15 0.16 %.)
inline constexpr int kEmitterSolveMaxSweeps = 200;
inline constexpr int kEmitterSolveToleranceLog2 = 11;
// Fixed partition of the surfaces for the parallel sweep (not the thread
// count, so the bits do not depend on it).
inline constexpr int kEmitterSolveBlocks = 2;

class HierarchySolveQ32 {
 public:
  // Needs bake.hierarchy (kUnsupported without); the bake must outlive this.
  Status Init(const Bake& bake);

  // Solves M = S + rho (K M + extra) for every node k and channel c:
  //   emitted_q32[k]            S, the same in every channel; leaves only;
  //   extra_irradiance_q32      null, or 3 per node (leaves only): irradiance
  //                             Q32 added at every sweep, e.g. adaptive
  //                             refine's first shot from sub-nodes the links
  //                             do not have;
  //   exitance_q32[3 k + c]     in: where the sweeps start (zeros, the slot's
  //                             previous solution, a first shot); out: M.
  // `pool` may be null (one thread). peak_floor_q32: the stopping rule's
  // peak exitance is at least this (adaptive refine passes its emitter's own
  // exitance, which is then not in emitted_q32, so the solve stops where it
  // would with the emitter in it). hint: null, or what the emitter's last
  // solve from a nearby start saw (SweepContraction); with it the rule may
  // stop after the first sweep, taking that solve's ratio of its first two
  // sweeps (at least 1/8) as this one's. seen: null, or where this solve's
  // contraction goes (valid when it took two sweeps or more). max_sweeps 0:
  // the set-up alone (the start's inner nodes pulled up and viewed, as a
  // result: exitance_q24() and AddEmitted follow it). Returns the sweeps it
  // took.
  int SolveRgb(const int64_t* emitted_q32, const int64_t* extra_irradiance_q32, int64_t* exitance_q32,
               WorkerPool* pool, int64_t peak_floor_q32 = 0, const SweepContraction* hint = nullptr,
               SweepContraction* seen = nullptr, int max_sweeps = kEmitterSolveMaxSweeps);
  // The next SolveRgb starts from `previous`, the array the last SolveRgb
  // solved into, with only these leaves changed (a fractional-emissivity
  // move): its set-up then pulls only their ancestors instead of the whole
  // hierarchy, with the same result. Ignored when `previous` is not the last
  // result (another solve, or AddEmitted on another array, came between).
  // The leaves must outlive the next SolveRgb.
  void StartNear(const int64_t* previous, const uint32_t* leaves, uint32_t count);
  // Above n / kSparseSetUpShare changed leaves the set-up pulls everything
  // (on both threads) rather than the changed leaves' ancestors (on one).
  static constexpr uint32_t kSparseSetUpShare = 8;
  // Adds emitted_q32 (per node, leaves only, the same in every channel) to
  // the leaves of exitance_q32 and pulls the inner nodes up again;
  // exitance_q24() follows. Adaptive refine solves without its emitter's
  // own exitance (its first shot stands for it) and adds it after. On the
  // array the last SolveRgb solved into, only the emitting leaves'
  // ancestors are pulled, and a StartNear from it still applies.
  void AddEmitted(const int64_t* emitted_q32, int64_t* exitance_q32);
  // exitance_q32 = rho x irradiance_q32 (3 per node) on the leaves, 0 on the
  // inner nodes (SolveRgb pulls them up): a new light's first bounce when
  // its first shot is known (adaptive refine), so the sweeps start one
  // bounce ahead of zeros.
  void ReflectedStart(const int64_t* irradiance_q32, int64_t* exitance_q32) const;
  // rho x (shot_now - shot_before) at leaf k, channel ch, Q32 (saturated):
  // an adaptive-refine move's change of first bounce, known before any
  // sweep, so its warm start can take it in.
  int64_t ReflectedChange(uint32_t k, int ch, int64_t shot_now, int64_t shot_before) const;
  // exitance_q32 = emitted_q32 + rho x shot_q32 on the leaves (both per
  // node, the same in every channel), 0 on the inner nodes: a new FE light's
  // start, its emission and its first bounce. The same bits as
  // ReflectedStart of the shot in every channel, then the emission added.
  void EmittedAndReflectedStart(const int64_t* emitted_q32, const int64_t* shot_q32, int64_t* exitance_q32) const;
  // exitance_q32 as int32 Q24 (kGatherFracBits), 4 per node (channels 0-2
  // and a zero), as the last
  // SolveRgb left it: what LeavesToVertices reads.
  const int32_t* exitance_q24() const { return view_[0].data(); }
  uint32_t node_count() const { return static_cast<uint32_t>(child_weight_q32_.size()); }
  // Gather and moment entries a sweep reads: what a sweep costs.
  size_t sweep_entries() const { return gather_.size() + inner_gather_.size() + moment_entries_; }

 private:
  struct Sweep;
  void SweepBlock(Sweep* sweep, int block);
  void PullNode(uint32_t k, int64_t* b, int32_t* view, int32_t* rows);
  void Pull(uint32_t begin, uint32_t end, int64_t* b, int32_t* view, int32_t* rows);
  void ViewChangedLeaves(int64_t* b);
  void MarkAncestors(uint32_t k, uint32_t* dirty);
  void PullMarked(uint32_t dirty, int64_t* b);
  void SetView(uint32_t k, const int64_t* b, int32_t* view, int32_t* rows) const;
  int32_t ToView(int64_t b_q32) const;
  using BlockStep = void (HierarchySolveQ32::*)(Sweep* sweep, int block);
  void RunOnBlocks(WorkerPool* pool, Sweep* sweep, BlockStep step);
  // A block's inner nodes pulled up from its leaves, and its view (view_[0]).
  void ViewBlock(Sweep* sweep, int block);
  void ExtrapolateBlock(Sweep* sweep, int block);
  void AssignBlocks();
  // gather_, inner_gather_, gradient_ and their offsets, moments_'s shift,
  // view_limit_ and vector_ (surface_emitter_gather_lists.cc).
  void BuildGatherLists();
  int32_t ToMomentView(int64_t m_q32) const;
  // a += m x 2^t (t the moment weights' shift), saturated.
  void AddMomentSum(const int64_t m[3], int64_t a[3]) const;

  const BakeHierarchy* h_ = nullptr;
  // Node k gathers from leaves over entries [gather_offsets_[k],
  // gather_offsets_[k + 1]) and from inner nodes over inner_gather_'s
  // [inner_offsets_[k], inner_offsets_[k + 1]) (with their moment weights);
  // an inner node's gradients (Q8.23 per metre, u and v) are at
  // gradient_[2 (gradient_offsets_[k] + i)] for its i-th entry, the leaf
  // sources' first.
  std::vector<uint32_t> gather_offsets_, inner_offsets_, gradient_offsets_;
  std::vector<EmitterGatherEntry> gather_;
  std::vector<EmitterInnerSourceEntry> inner_gather_;
  std::vector<int32_t> gradient_;
  // The moment terms' shift and the inner-node numbering (its entries are
  // moved into inner_gather_ at Init; moment_entries_ counts them).
  EmitterMomentTable moments_;
  size_t moment_entries_ = 0;
  std::vector<uint64_t> child_weight_q32_;  // area over the parent's, 2^32 = all
  std::vector<int32_t> centre_uv_q16_;      // 2 per node, surface frame, m
  std::vector<uint64_t> rho_q32_;           // 3 per node (leaves), 2^32 = 1
  std::vector<uint32_t> run_begin_;         // first node of each tree, then node_count
  std::vector<uint32_t> block_runs_[kEmitterSolveBlocks];  // runs of each block, ascending (AssignBlocks)
  bool vector_ = false;                     // the AVX2 gathers (Init)
  int threads_ = 1;                         // of the current SolveRgb
  int32_t view_limit_ = 0;                  // |exitance| read by a gather, Q24 (Init)
  std::vector<int64_t> g0_, gu_, gv_;       // gathered a + b u + c v, Q32, 3 per node
  // First moment of exitance about the node's centre (Q32 x m, u and v, 3
  // per node; 0 at a leaf), pulled up with the exitance.
  std::vector<int64_t> mu_, mv_;
  std::vector<int64_t> delta_;              // each leaf's change in its last sweep, Q32, 3 per node
  // StartNear: the array the last SolveRgb solved into (null after a whole
  // AddEmitted), and the next solve's start; per node a mark and a list for
  // the ancestors to pull.
  const int64_t* last_result_ = nullptr;
  const int64_t* near_previous_ = nullptr;
  const uint32_t* near_leaves_ = nullptr;
  uint32_t near_count_ = 0;
  std::vector<uint8_t> dirty_;
  std::vector<uint32_t> dirty_list_;
  // Per block, every node's exitance as that block's gathers read it, and
  // every inner node's row (kInnerRowInts: its exitance view again and its
  // moment, Q20 x m) at inner_row_[block] (64-byte aligned in inner_rows_).
  std::vector<int32_t> view_[kEmitterSolveBlocks];
  std::vector<int32_t> inner_rows_[kEmitterSolveBlocks];
  int32_t* inner_row_[kEmitterSolveBlocks] = {};
};

}  // namespace relight
