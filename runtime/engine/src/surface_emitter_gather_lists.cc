// The emitter solve's gather lists (surface_emitter_solve.h), built once at
// Init: per receiver its links from leaves and from inner nodes (with their
// moment weights), the inner receivers' gradients, and the view's bound.
// Scaling and overflow: surface_emitter_solve.cc's top comment.
#include <cstdint>
#include <vector>

#include "surface_emitter_gather_avx2.h"
#include "surface_emitter_moments.h"
#include "surface_emitter_solve.h"

namespace relight {

void HierarchySolveQ32::BuildGatherLists() {
  const BakeHierarchy& h = *h_;
  const uint32_t n = h.node_count();
  BuildEmitterMoments(h, &moments_);
  // Per receiver, the links from leaves (gather_) and those from inner nodes
  // (inner_gather_, with their moment weights), each in link order; an inner
  // receiver's gradients are its leaf-source links' then its inner-source
  // links'. The sums are exact in int64 (the bound below), so splitting them
  // changes no bit.
  gather_offsets_.assign(size_t{n} + 1, 0);
  inner_offsets_.assign(size_t{n} + 1, 0);
  const auto count = [&](uint32_t to, uint32_t from) {
    ++(h.leaf(from) ? gather_offsets_ : inner_offsets_)[to + 1];
  };
  for (uint32_t i = 0; i < h.link_count(); ++i) {
    if (h.link_f_pq[i] != 0) count(h.link_p[i], h.link_q[i]);
    if (h.link_f_qp[i] != 0) count(h.link_q[i], h.link_p[i]);
  }
  gradient_offsets_.assign(size_t{n} + 1, 0);
  for (uint32_t k = 0; k < n; ++k) {
    gradient_offsets_[k + 1] =
        gradient_offsets_[k] + (h.leaf(k) ? 0 : gather_offsets_[k + 1] + inner_offsets_[k + 1]);
    gather_offsets_[k + 1] += gather_offsets_[k];
    inner_offsets_[k + 1] += inner_offsets_[k];
  }
  gather_.assign(gather_offsets_[n], EmitterGatherEntry{0, 0});
  inner_gather_.assign(inner_offsets_[n], EmitterInnerSourceEntry{0, 0, 0, 0});
  gradient_.assign(size_t{gradient_offsets_[n]} * 2, 0);
  std::vector<uint32_t> fill(n, 0), inner_fill(n, 0), moment_fill(n, 0);
  const auto add = [&](uint32_t to, uint32_t from, uint32_t f, uint32_t f_rev, const int32_t* g) {
    const uint32_t leaf_count = gather_offsets_[to + 1] - gather_offsets_[to];
    uint32_t at = 0;  // the entry's place among the receiver's gradients
    if (h.leaf(from)) {
      at = fill[to]++;
      gather_[gather_offsets_[to] + at] = EmitterGatherEntry{from, f};
    } else {
      const uint32_t i = inner_fill[to]++;
      EmitterInnerSourceEntry& e = inner_gather_[inner_offsets_[to] + i];
      e = EmitterInnerSourceEntry{moments_.inner_before[from], f, 0, 0};
      if (f_rev != 0) {  // the moment table's rule: a term where the reverse factor is known
        const EmitterMomentEntry& m = moments_.entries[moments_.offsets[to] + moment_fill[to]++];
        e.wu = m.wu;
        e.wv = m.wv;
      }
      at = leaf_count + i;
    }
    if (h.leaf(to)) return;  // a leaf's links carry no gradient
    gradient_[2 * size_t{gradient_offsets_[to] + at}] = g[0];
    gradient_[2 * size_t{gradient_offsets_[to] + at} + 1] = g[1];
  };
  for (uint32_t i = 0; i < h.link_count(); ++i) {
    if (h.link_f_pq[i] != 0)
      add(h.link_p[i], h.link_q[i], h.link_f_pq[i], h.link_f_qp[i], &h.link_g_pq[2 * size_t{i}]);
    if (h.link_f_qp[i] != 0)
      add(h.link_q[i], h.link_p[i], h.link_f_qp[i], h.link_f_pq[i], &h.link_g_qp[2 * size_t{i}]);
  }
  // The largest sum a gather can multiply the view by (see the top comment).
  uint64_t row_max = 1;
  bool vector_ok = true;
  for (uint32_t k = 0; k < n; ++k) {
    uint64_t f = 0, du = 0, dv = 0;
    for (uint32_t e = gather_offsets_[k]; e < gather_offsets_[k + 1]; ++e) {
      f += gather_[e].f;
      if (gather_[e].f >= (uint32_t{1} << 31)) vector_ok = false;  // _mm256_mul_epi32 is signed
    }
    for (uint32_t e = inner_offsets_[k]; e < inner_offsets_[k + 1]; ++e) {
      f += inner_gather_[e].f;
      if (inner_gather_[e].f >= (uint32_t{1} << 31)) vector_ok = false;
    }
    const uint64_t w = EmitterMomentRowSum(moments_, k);  // <= 2^63 - 1
    f = f + w < f || f + w > static_cast<uint64_t>(INT64_MAX) ? static_cast<uint64_t>(INT64_MAX) : f + w;
    for (uint32_t e = 2 * gradient_offsets_[k]; e < 2 * gradient_offsets_[k + 1]; e += 2) {
      du += static_cast<uint64_t>(gradient_[e] < 0 ? -int64_t{gradient_[e]} : gradient_[e]);
      dv += static_cast<uint64_t>(gradient_[e + 1] < 0 ? -int64_t{gradient_[e + 1]} : gradient_[e + 1]);
    }
    for (uint64_t s : {f, du, dv})
      if (s > row_max) row_max = s;
  }
  const uint64_t limit = static_cast<uint64_t>(INT64_MAX) / row_max;
  view_limit_ = limit >= uint64_t{INT32_MAX} ? INT32_MAX : static_cast<int32_t>(limit);
  vector_ = vector_ok && EmitterGatherHasAvx2();
}

}  // namespace relight
