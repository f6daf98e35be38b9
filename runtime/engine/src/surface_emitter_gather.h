// The emitter solve's gathers on the scalar path (surface_emitter_solve.cc):
// the contract and the products are surface_emitter_gather_avx2.h's, whose
// vector bodies give the same bits.
#pragma once

#include <cstdint>

#include "surface_emitter_gather_avx2.h"

namespace relight {

void GatherLeaf(const EmitterGatherEntry* e, uint32_t count, const int32_t* view, int64_t a[3]);
void GatherInner(const EmitterGatherEntry* e, const int32_t* g, uint32_t count, const int32_t* view, int64_t a[3],
                 int64_t u[3], int64_t v[3]);
void GatherLeafFromInner(const EmitterInnerSourceEntry* e, uint32_t count, const int32_t* rows, int64_t a[3],
                         int64_t m[3]);
void GatherInnerFromInner(const EmitterInnerSourceEntry* e, const int32_t* g, uint32_t count, const int32_t* rows,
                          int64_t a[3], int64_t u[3], int64_t v[3], int64_t m[3]);

}  // namespace relight
