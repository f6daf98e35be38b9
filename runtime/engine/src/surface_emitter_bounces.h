// Precomputed interreflection for new run-time emitters (issue 15): the
// light a new emitter leaves in the scene beyond its first bounce is smooth
// in where the emitter sits, so it is tabulated once at Open per "coarse
// source": a node of a surface's tree of at most a few square metres. A new
// light then starts its sweeps from its emission, its exact first bounce and
// the table's later bounces (each coarse source's, weighted by the share of
// its area the emitter covers); the sweeps correct what the table got
// wrong, and the solver's stopping rule decides when, as it does for any
// start, so the table changes how many sweeps a placement takes, not what it
// converges to (within the rule's tolerance).
//
// Why not store it in the bake: it is 6 bytes per leaf per coarse source
// (26 MB on the 16k-patch living room), and the engine computes it with the
// same solver that then uses it, in a few seconds at Open.
//
// Scaling: a coarse source's later bounces T (Q32 exitance per unit
// luminance over the whole source, |T| < 2^47) are kept as int16 with a
// per-source shift s (T ~ t 2^s); a placement adds t x c >> (32 - s) per leaf
// and channel, c the covered share of the source's area (UQ32, <= 2^32), in
// int64 (|t c| < 2^47). Integer only; Build allocates, AddTo does not.
#pragma once

#include <cstdint>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/engine/surface_emitter.h"
#include "surface_emitter_extrapolate.h"

namespace relight {

// How finely the scene is cut: sources of at most 1/kBounceSources of the
// scene's surface area (fewer where the table would not fit its budget).
// The 16k-patch living room gets 279 sources (26 MB, Open +3 s) and the
// paper's room 424 (4.6 MB, +0.7 s): new lights there take one sweep
// (docs/hierarchy.md "Later bounces tabulated at Open").
inline constexpr int kBounceSources = 128;
// Open's work: sources x the solver's gather and moment entries at most
// this (one solve per source, ~5 sweeps each). The 16k-patch living room
// (2.26 M entries a sweep) stays at its 279 sources, about 3.5 s; a scene
// with ten times the links gets a tenth of the sources instead of ten times
// the start-up.
inline constexpr int64_t kBounceTableWork = int64_t{700} << 20;

class EmitterBounceTable {
 public:
  // Cuts every tree into coarse sources: the nodes of area at most A whose
  // parent is larger (or a leaf larger than that); A is max_area_q32 (> 0),
  // else the scene's area / kBounceSources, doubled until sources x leaves x
  // 6 bytes fit budget_bytes and there are at most max_sources. Allocates
  // the table, all zero. budget_bytes <= 0: no table.
  void Partition(const BakeHierarchy& h, int64_t budget_bytes, uint32_t max_sources = UINT32_MAX,
                 int64_t max_area_q32 = 0);

  uint32_t source_count() const { return static_cast<uint32_t>(source_node_.size()); }
  uint32_t source_node(uint32_t j) const { return source_node_[j]; }
  size_t bytes() const { return table_.size() * sizeof(int16_t); }
  // The largest area a source may have (Q32 m^2; 0 without a table).
  int64_t source_area_q32() const { return source_node_.empty() ? 0 : source_area_q32_; }
  // Coverage (UQ32 per node, leaves) of source j: 2^32 on its leaves, else 0.
  void UnitCoverage(uint32_t j, int64_t* coverage_q32) const;
  // Source j's later bounces: solved - start on the leaves (3 per node,
  // Q32), and how its sweeps contracted.
  void Store(uint32_t j, const int64_t* solved_q32, const int64_t* start_q32, const SweepContraction& seen);

  // b += sum over the sources under `root` of (covered share) x T, on every
  // leaf and channel (saturated). Returns the contraction of the source
  // with the largest covered share (a hint for the first sweep's stop),
  // or null if none is valid or nothing is covered.
  const SweepContraction* AddTo(const int64_t* coverage_q32, uint32_t root, int64_t* b);
  // b += the table's change from one coverage to another: per source the
  // change of covered share times its later bounces, only where the share
  // changed (an emitter moved within a source changes nothing). The roots
  // may be different surfaces.
  void AddChange(const int64_t* now_q32, uint32_t now_root, const int64_t* before_q32, uint32_t before_root,
                 int64_t* b);

 private:
  const BakeHierarchy* h_ = nullptr;
  std::vector<uint32_t> source_node_;     // per source, its node
  std::vector<uint32_t> source_of_;       // per node, its source (kBakeNoIndex above the sources)
  std::vector<uint32_t> tree_end_;        // per root, one past its last node
  std::vector<uint32_t> leaves_;          // leaf nodes ascending; the table's leaf order
  std::vector<int16_t> table_;            // source-major: 3 per leaf
  std::vector<int8_t> shift_;             // per source, s
  int64_t source_area_q32_ = 0;
  std::vector<SweepContraction> contraction_;
  // share_[j] += sign x sum of area x coverage over root's covered leaves in
  // source j; [first, last] widened to the sources touched.
  void AddShares(const int64_t* coverage_q32, uint32_t root, int sign, uint32_t* first, uint32_t* last);
  // b += share_[j] / area_j x T_j over [first, last], share_ cleared; the
  // hint of the largest share (AddTo).
  const SweepContraction* AddSharesTimesTable(uint32_t first, uint32_t last, int64_t* b);

  std::vector<Int128> share_;             // AddTo's scratch, per source: sum of area x coverage
};

}  // namespace relight
