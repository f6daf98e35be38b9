// Source-moment terms of the emitter solve (surface_emitter_moments.h).
//
// Scaling: f (UQ0.32) x g_rev (Q8.23 per metre) / f_rev (UQ0.32) is Q23
// per metre; x 2^13 gives Q36, in Int128 (f g_rev < 2^63, x 2^13 < 2^76).
#include "surface_emitter_moments.h"

#include "relight/base/fixed_ops.h"

namespace relight {

void BuildEmitterMoments(const BakeHierarchy& h, EmitterMomentTable* table) {
  const uint32_t n = h.node_count();
  table->inner_before.assign(size_t{n} + 1, 0);
  for (uint32_t k = 0; k < n; ++k) table->inner_before[k + 1] = table->inner_before[k] + (h.leaf(k) ? 0 : 1);
  std::vector<uint32_t>& offsets = table->offsets;
  offsets.assign(size_t{n} + 1, 0);
  // The baker's rule: a term where the link gathers (f > 0), its reverse
  // factor is known (f_rev > 0) and the source is an inner node.
  const auto counts = [&](uint32_t i, bool forward) {
    const uint32_t from = forward ? h.link_q[i] : h.link_p[i];
    return h.link_f_pq[i] != 0 && h.link_f_qp[i] != 0 && !h.leaf(from);
  };
  for (uint32_t i = 0; i < h.link_count(); ++i) {
    if (counts(i, true)) ++offsets[h.link_p[i] + 1];
    if (counts(i, false)) ++offsets[h.link_q[i] + 1];
  }
  for (uint32_t k = 0; k < n; ++k) offsets[k + 1] += offsets[k];
  // Two passes over the links: the largest weight sets the shift, then the
  // weights are stored (no transient array of Int128 weights: 27 MB on the
  // 16k-patch room).
  const auto weight = [](uint32_t f, uint32_t f_rev, int32_t g_rev) {
    return DivRound(static_cast<Int128>(f) * g_rev * (Int128{1} << (kMomentWeightFracBits - 23)), f_rev);
  };
  Int128 w_max = 0;
  for (uint32_t i = 0; i < h.link_count(); ++i) {
    for (int a = 0; a < 2; ++a) {
      Int128 w[2] = {0, 0};
      if (counts(i, true)) w[0] = weight(h.link_f_pq[i], h.link_f_qp[i], h.link_g_qp[2 * size_t{i} + a]);
      if (counts(i, false)) w[1] = weight(h.link_f_qp[i], h.link_f_pq[i], h.link_g_pq[2 * size_t{i} + a]);
      for (Int128 x : w)
        if ((x < 0 ? -x : x) > w_max) w_max = x < 0 ? -x : x;
    }
  }
  table->shift = 0;
  while ((w_max >> table->shift) > INT32_MAX) ++table->shift;
  // In the gathers' order (surface_emitter_solve.cc fills its entries the same way).
  table->entries.assign(offsets[n], EmitterMomentEntry{0, 0, 0});
  std::vector<uint32_t> fill(n, 0);
  const auto add = [&](uint32_t to, uint32_t from, uint32_t f, uint32_t f_rev, const int32_t* g_rev) {
    EmitterMomentEntry& e = table->entries[offsets[to] + fill[to]++];
    e.source = table->inner_before[from];
    e.wu = static_cast<int32_t>(RoundShiftSat64(weight(f, f_rev, g_rev[0]), -table->shift));
    e.wv = static_cast<int32_t>(RoundShiftSat64(weight(f, f_rev, g_rev[1]), -table->shift));
  };
  for (uint32_t i = 0; i < h.link_count(); ++i) {
    const int32_t* g_pq = &h.link_g_pq[2 * size_t{i}];
    const int32_t* g_qp = &h.link_g_qp[2 * size_t{i}];
    if (counts(i, true)) add(h.link_p[i], h.link_q[i], h.link_f_pq[i], h.link_f_qp[i], g_qp);
    if (counts(i, false)) add(h.link_q[i], h.link_p[i], h.link_f_qp[i], h.link_f_pq[i], g_pq);
  }
}

uint64_t EmitterMomentRowSum(const EmitterMomentTable& table, uint32_t k) {
  UInt128 sum = 0;
  for (uint32_t e = table.offsets[k]; e < table.offsets[k + 1]; ++e) {
    const EmitterMomentEntry& m = table.entries[e];
    sum += static_cast<UInt128>(m.wu < 0 ? -int64_t{m.wu} : m.wu);
    sum += static_cast<UInt128>(m.wv < 0 ? -int64_t{m.wv} : m.wv);
  }
  sum <<= table.shift;  // < 2^32 links x 2^32 x 2^t: fits while t < 64
  return sum > static_cast<UInt128>(INT64_MAX) ? static_cast<uint64_t>(INT64_MAX) : static_cast<uint64_t>(sum);
}

}  // namespace relight
