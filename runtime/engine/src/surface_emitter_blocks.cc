// How the emitter solve shares its sweeps between threads
// (surface_emitter_solve.h), once at Init: the surfaces dealt to the
// parallel blocks. The partition is part of the result (block Gauss-Seidel)
// and depends on the bake alone.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "surface_emitter_solve.h"

namespace relight {

// Whole surfaces (runs) dealt to the blocks, the costliest first, each to
// the block with the least work so far (the longest-processing-time rule):
// the surfaces' sizes are very uneven (the 16k room's two largest hold 45 %
// of its gather entries), and a split of the runs in node order left one
// thread 1.5x the other's work. A run's cost: its gather, gradient and
// moment entries (a multiply-add of three channels each) and kNodeCost per
// node (push, leaf update, pull, view). 100 balanced the 16k room's two
// blocks best (timed per block: 2.81 and 2.81 ms a sweep; 0: 3.09 and 3.56,
// 40: 2.91 and 3.00, 200: 2.88 and 2.92; 4.2 and 2.7 in node order).
// Depends on the bake only, so the bits do not depend on the thread count.
void HierarchySolveQ32::AssignBlocks() {
  constexpr uint64_t kNodeCost = 100;
  const uint32_t runs = static_cast<uint32_t>(run_begin_.size() - 1);
  std::vector<std::pair<uint64_t, uint32_t>> cost(runs);
  for (uint32_t r = 0; r < runs; ++r) {
    const uint32_t lo = run_begin_[r], hi = run_begin_[r + 1];
    cost[r] = {uint64_t{gather_offsets_[hi] - gather_offsets_[lo]} + (inner_offsets_[hi] - inner_offsets_[lo]) +
                   (gradient_offsets_[hi] - gradient_offsets_[lo]) +
                   (moments_.offsets[hi] - moments_.offsets[lo]) + kNodeCost * (hi - lo),
               r};
  }
  std::sort(cost.begin(), cost.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
  });
  uint64_t load[kEmitterSolveBlocks] = {};
  for (std::vector<uint32_t>& v : block_runs_) v.clear();
  for (const auto& [c, r] : cost) {
    int least = 0;
    for (int b = 1; b < kEmitterSolveBlocks; ++b)
      if (load[b] < load[least]) least = b;
    load[least] += c;
    block_runs_[least].push_back(r);
  }
  for (std::vector<uint32_t>& v : block_runs_) std::sort(v.begin(), v.end());  // sweep in node order
}

}  // namespace relight
