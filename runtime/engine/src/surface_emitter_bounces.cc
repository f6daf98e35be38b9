// Precomputed later bounces of coarse sources (surface_emitter_bounces.h).
#include "surface_emitter_bounces.h"

#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

// The coarse source of every node (kBakeNoIndex above them) for sources of
// at most max_area; returns how many. Nodes come parents first.
uint32_t CutIntoSources(const BakeHierarchy& h, int64_t max_area, std::vector<uint32_t>* source_of) {
  const uint32_t n = h.node_count();
  source_of->assign(n, kBakeNoIndex);
  uint32_t count = 0;
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t parent = h.node_parent[k];
    if (parent != kBakeNoIndex && (*source_of)[parent] != kBakeNoIndex) {
      (*source_of)[k] = (*source_of)[parent];
    } else if (h.leaf(k) || h.node_area[k] <= static_cast<uint64_t>(max_area)) {
      (*source_of)[k] = count++;
    }
  }
  return count;
}

}  // namespace

void EmitterBounceTable::Partition(const BakeHierarchy& h, int64_t budget_bytes, uint32_t max_sources,
                                   int64_t max_area_q32) {
  h_ = &h;
  source_node_.clear();
  leaves_.clear();
  table_.clear();
  const uint32_t n = h.node_count();
  for (uint32_t k = 0; k < n; ++k)
    if (h.leaf(k)) leaves_.push_back(k);
  uint64_t largest_root = 0;
  Int128 scene_area = 0;
  for (uint32_t k = 0; k < n; ++k) {
    if (h.node_parent[k] != kBakeNoIndex) continue;
    if (h.node_area[k] > largest_root) largest_root = h.node_area[k];
    scene_area += h.node_area[k];
  }
  const Int128 per_source = static_cast<Int128>(leaves_.size()) * 3 * sizeof(int16_t);
  uint32_t count = 0;
  const Int128 share = scene_area / kBounceSources;
  int64_t area = max_area_q32 > 0 ? max_area_q32 : (share > INT64_MAX ? INT64_MAX : static_cast<int64_t>(share));
  if (area < 1) area = 1;
  while (true) {
    count = CutIntoSources(h, area, &source_of_);
    if (budget_bytes > 0 && per_source * count <= budget_bytes && count <= max_sources) break;
    // One source per tree is as coarse as it gets: then there is no table.
    if (budget_bytes <= 0 || static_cast<uint64_t>(area) >= largest_root || area > (INT64_MAX >> 1)) {
      count = 0;
      source_of_.assign(n, kBakeNoIndex);
      break;
    }
    area *= 2;
  }
  source_area_q32_ = area;
  source_node_.assign(count, kBakeNoIndex);
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t j = source_of_[k];
    if (j != kBakeNoIndex && source_node_[j] == kBakeNoIndex) source_node_[j] = k;
  }
  tree_end_.assign(n, 0);
  for (uint32_t k = 0, root = 0; k <= n; ++k) {
    if (k == n || h.node_parent[k] == kBakeNoIndex) {
      if (k > 0) tree_end_[root] = k;
      root = k;
    }
  }
  table_.assign(size_t{count} * leaves_.size() * 3, 0);
  shift_.assign(count, 0);
  contraction_.assign(count, SweepContraction{});
  share_.assign(count, 0);
}

void EmitterBounceTable::UnitCoverage(uint32_t j, int64_t* coverage_q32) const {
  for (uint32_t k = 0; k < h_->node_count(); ++k)
    coverage_q32[k] = h_->leaf(k) && source_of_[k] == j ? int64_t{1} << 32 : 0;
}

void EmitterBounceTable::Store(uint32_t j, const int64_t* solved, const int64_t* start, const SweepContraction& seen) {
  const size_t count = leaves_.size();
  int64_t largest = 0;
  for (size_t i = 0; i < count; ++i)
    for (int ch = 0; ch < 3; ++ch) {
      const size_t at = 3 * size_t{leaves_[i]} + ch;
      const int64_t t = SubSat64(solved[at], start[at]);
      const int64_t magnitude = t < 0 ? (t == INT64_MIN ? INT64_MAX : -t) : t;
      if (magnitude > largest) largest = magnitude;
    }
  int s = 0;
  while (s < 32 && (largest >> s) >= (int64_t{1} << 15)) ++s;
  shift_[j] = static_cast<int8_t>(s);
  int16_t* t16 = &table_[size_t{j} * count * 3];
  for (size_t i = 0; i < count; ++i)
    for (int ch = 0; ch < 3; ++ch) {
      const size_t at = 3 * size_t{leaves_[i]} + ch;
      const int64_t t = RoundShiftSat64(SubSat64(solved[at], start[at]), -s);
      t16[3 * i + static_cast<size_t>(ch)] = static_cast<int16_t>(t > 32767 ? 32767 : (t < -32767 ? -32767 : t));
    }
  contraction_[j] = seen;
}

void EmitterBounceTable::AddShares(const int64_t* coverage_q32, uint32_t root, int sign, uint32_t* first,
                                   uint32_t* last) {
  if (root >= tree_end_.size()) return;
  const BakeHierarchy& h = *h_;
  for (uint32_t k = root; k < tree_end_[root]; ++k) {
    if (!h.leaf(k) || coverage_q32[k] == 0) continue;
    const uint32_t j = source_of_[k];
    if (*first == kBakeNoIndex || j < *first) *first = j;
    if (j > *last) *last = j;
    share_[j] += sign * static_cast<Int128>(h.node_area[k]) * coverage_q32[k];
  }
}

const SweepContraction* EmitterBounceTable::AddTo(const int64_t* coverage_q32, uint32_t root, int64_t* b) {
  if (source_node_.empty()) return nullptr;
  uint32_t first = kBakeNoIndex, last = 0;
  AddShares(coverage_q32, root, 1, &first, &last);
  return AddSharesTimesTable(first, last, b);
}

void EmitterBounceTable::AddChange(const int64_t* now_q32, uint32_t now_root, const int64_t* before_q32,
                                   uint32_t before_root, int64_t* b) {
  if (source_node_.empty()) return;
  uint32_t first = kBakeNoIndex, last = 0;
  AddShares(now_q32, now_root, 1, &first, &last);
  AddShares(before_q32, before_root, -1, &first, &last);
  (void)AddSharesTimesTable(first, last, b);
}

const SweepContraction* EmitterBounceTable::AddSharesTimesTable(uint32_t first, uint32_t last, int64_t* b) {
  if (first == kBakeNoIndex) return nullptr;
  const BakeHierarchy& h = *h_;
  const SweepContraction* hint = nullptr;
  Int128 largest = 0;
  const size_t count = leaves_.size();
  for (uint32_t j = first; j <= last; ++j) {
    if (share_[j] == 0) continue;
    // The covered share of the source's area, Q32 (|c| <= 2^32; < 0 only in
    // AddChange, where the share before is taken away).
    const int64_t c = static_cast<int64_t>(DivRound(share_[j], static_cast<Int128>(h.node_area[source_node_[j]])));
    if (share_[j] > largest) {
      largest = share_[j];
      hint = contraction_[j].valid ? &contraction_[j] : nullptr;
    }
    share_[j] = 0;
    if (c == 0) continue;
    const int shift = 32 - shift_[j];
    const int64_t half = shift > 0 ? int64_t{1} << (shift - 1) : 0;
    const int16_t* t16 = &table_[size_t{j} * count * 3];
    for (size_t i = 0; i < count; ++i) {
      int64_t* leaf = b + 3 * size_t{leaves_[i]};
      for (int ch = 0; ch < 3; ++ch)  // |t c| < 2^15 x 2^33
        leaf[ch] = AddSat64(leaf[ch], (int64_t{t16[3 * i + static_cast<size_t>(ch)]} * c + half) >> shift);
    }
  }
  return hint;
}

}  // namespace relight
