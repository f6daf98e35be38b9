// The AVX2 body of the emitter solve's gathers (surface_emitter_solve.cc), in
// its own file because the rest of the runtime is built with
// -mgeneral-regs-only. Integer instructions only (no_float_check.sh checks
// the object code). It forms exactly the scalar path's products and sums
// them in int64 as it does, so the results are bit-identical.
#pragma once

#include <cstdint>

namespace relight {

// One link of a gather: the source node and its factor f, UQ0.32.
struct EmitterGatherEntry {
  uint32_t source, f;
};

// One source-moment term of a gather (docs/hierarchy.md "Bias and its fix"):
// the inner source node's index among the inner nodes and its weights
// f g_rev / f_rev (u, v), Q(36 - t) per metre, t the solver's moment shift.
struct EmitterMomentEntry {
  uint32_t source;
  int32_t wu, wv;
};

// A link of a gather whose source is an inner node: its index among the
// inner nodes, its factor f (UQ0.32) and its moment weights (as
// EmitterMomentEntry; zero when the link has no reverse factor). The
// source's exitance and moment are one row of kInnerRowInts int32
// (InnerRow), so one entry reads one cache line, not two places.
struct EmitterInnerSourceEntry {
  uint32_t source, f;
  int32_t wu, wv;
};

// An inner node's row: exitance view (Q24) channels 0-2, a zero, moment u
// (Q20 x m) 0-2, a zero, moment v 0-2, a zero, then padding to 64 bytes.
inline constexpr uint32_t kInnerRowInts = 16;

// True when the CPU runs AVX2 (recombine_avx2.h CpuHasAvx2: honours
// RELIGHT_FORCE_SCALAR).
bool EmitterGatherHasAvx2();

// view: 4 int32 per node (channels 0-2 and a zero).
// a[c] = sum f x view[4 source + c]; the vector path needs every f < 2^31
// (the caller checks once). For an inner receiver also u[c], v[c] = sum
// g[2 i], g[2 i + 1] x view. Scaling and overflow: the caller's (the sums'
// bound is checked at open; surface_emitter_solve.cc).
void GatherLeafAvx2(const EmitterGatherEntry* e, uint32_t count, const int32_t* view, int64_t a[3]);
void GatherInnerAvx2(const EmitterGatherEntry* e, const int32_t* g, uint32_t count, const int32_t* view,
                     int64_t a[3], int64_t u[3], int64_t v[3]);
// Inner sources (rows: kInnerRowInts int32 per inner node, InnerRow's
// layout): a[c] += sum f x b, m[c] = sum wu x mu + wv x mv, and for an inner
// receiver (the other) u[c] += sum g[2 i] x b, v[c] += sum g[2 i + 1] x b.
// Every f < 2^31 as above.
void GatherLeafFromInnerAvx2(const EmitterInnerSourceEntry* e, uint32_t count, const int32_t* rows, int64_t a[3],
                             int64_t m[3]);
void GatherInnerFromInnerAvx2(const EmitterInnerSourceEntry* e, const int32_t* g, uint32_t count, const int32_t* rows,
                              int64_t a[3], int64_t u[3], int64_t v[3], int64_t m[3]);

}  // namespace relight
