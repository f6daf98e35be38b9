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
// m[c] = sum wu x moment[8 source + c] + wv x moment[8 source + 4 + c]
// (moment: 8 int32 per inner node, u channels 0-2, 0, v channels 0-2, 0).
void GatherMomentAvx2(const EmitterMomentEntry* e, uint32_t count, const int32_t* moment, int64_t m[3]);

}  // namespace relight
