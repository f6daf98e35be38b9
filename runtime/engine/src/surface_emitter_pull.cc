// The emitter solve's pull (surface_emitter_solve.h): inner nodes from their
// children, area-weighted, with the first moment of exitance; and a move's
// set-up that pulls only the changed leaves' ancestors (StartNear). Scaling
// and overflow: surface_emitter_solve.cc's top comment ("Pull").
#include <algorithm>
#include <cstdint>
#include <functional>

#include "relight/base/fixed_ops.h"
#include "surface_emitter_moments.h"
#include "surface_emitter_solve.h"

namespace relight {

void HierarchySolveQ32::PullNode(uint32_t k, int64_t* b, int32_t* view, int32_t* rows) {
  const BakeHierarchy& h = *h_;
  const uint32_t first = h.node_first_child[k], last = first + h.node_child_count[k];
  Int128 sum[3] = {0, 0, 0}, su[3] = {0, 0, 0}, sv[3] = {0, 0, 0};
  const int32_t* ck = &centre_uv_q16_[2 * size_t{k}];
  for (uint32_t c = first; c < last; ++c) {
    // At most 2^32 (the bake's check makes a parent's area the sum of its
    // children's): as int64, so each product is one signed 64 x 64 multiply.
    const Int128 w = static_cast<int64_t>(child_weight_q32_[c]);
    const int32_t* cc = &centre_uv_q16_[2 * size_t{c}];
    const int64_t du = int64_t{cc[0]} - ck[0], dv = int64_t{cc[1]} - ck[1];  // Q16 m
    for (int ch = 0; ch < 3; ++ch) {
      const size_t i = 3 * size_t{c} + ch;
      sum[ch] += w * b[i];
      // m_parent = sum w_c (m_c + B_c (c_c - c_parent)), Q32 x m.
      su[ch] += w * AddSat64(mu_[i], OffsetMomentQ32(b[i], du));
      sv[ch] += w * AddSat64(mv_[i], OffsetMomentQ32(b[i], dv));
    }
  }
  for (int ch = 0; ch < 3; ++ch) {
    b[3 * size_t{k} + ch] = RoundShiftSat64(sum[ch], -32);
    mu_[3 * size_t{k} + ch] = RoundShiftSat64(su[ch], -32);
    mv_[3 * size_t{k} + ch] = RoundShiftSat64(sv[ch], -32);
  }
  SetView(k, b, view, rows);
}

void HierarchySolveQ32::Pull(uint32_t begin, uint32_t end, int64_t* b, int32_t* view, int32_t* rows) {
  for (uint32_t k = end; k-- > begin;) {  // children come after their parents
    if (!h_->leaf(k)) PullNode(k, b, view, rows);
  }
}

void HierarchySolveQ32::StartNear(const int64_t* previous, const uint32_t* leaves, uint32_t count) {
  near_previous_ = previous;
  near_leaves_ = leaves;
  near_count_ = count;
}

// Marks node k's ancestors for PullMarked, listing each once.
void HierarchySolveQ32::MarkAncestors(uint32_t k, uint32_t* dirty) {
  const BakeHierarchy& h = *h_;
  for (uint32_t p = h.node_parent[k]; p != kBakeNoIndex && dirty_[p] == 0; p = h.node_parent[p]) {
    dirty_[p] = 1;
    dirty_list_[(*dirty)++] = p;
  }
}

// The marked nodes pulled deepest first (children come after their
// parents), their marks cleared.
void HierarchySolveQ32::PullMarked(uint32_t dirty, int64_t* b) {
  std::sort(dirty_list_.begin(), dirty_list_.begin() + dirty, std::greater<uint32_t>());  // in place
  for (uint32_t i = 0; i < dirty; ++i) {
    PullNode(dirty_list_[i], b, view_[0].data(), inner_row_[0]);
    dirty_[dirty_list_[i]] = 0;
  }
}

// The set-up of a solve that starts from the last one's result with a few
// leaves changed (StartNear): those leaves' view, then their ancestors pulled,
// deepest first -- the same values a whole pull gives, since every other
// node still holds what the last solve's own pull left.
void HierarchySolveQ32::ViewChangedLeaves(int64_t* b) {
  uint32_t dirty = 0;
  for (uint32_t i = 0; i < near_count_; ++i) {
    const uint32_t k = near_leaves_[i];
    SetView(k, b, view_[0].data(), inner_row_[0]);
    MarkAncestors(k, &dirty);
  }
  PullMarked(dirty, b);
}

}  // namespace relight
