// Scalar emitter gathers: see surface_emitter_gather.h.
#include "surface_emitter_gather.h"

#include <cstddef>

namespace relight {

void GatherLeaf(const EmitterGatherEntry* e, uint32_t count, const int32_t* view, int64_t a[3]) {
  int64_t a0 = 0, a1 = 0, a2 = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const int32_t* src = &view[4 * size_t{e[i].source}];
    const int64_t f = e[i].f;
    a0 += f * src[0];
    a1 += f * src[1];
    a2 += f * src[2];
  }
  a[0] = a0;
  a[1] = a1;
  a[2] = a2;
}

void GatherInner(const EmitterGatherEntry* e, const int32_t* g, uint32_t count, const int32_t* view, int64_t a[3],
                 int64_t u[3], int64_t v[3]) {
  int64_t a0 = 0, a1 = 0, a2 = 0, u0 = 0, u1 = 0, u2 = 0, v0 = 0, v1 = 0, v2 = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const int32_t* src = &view[4 * size_t{e[i].source}];
    const int64_t f = e[i].f, du = g[2 * i], dv = g[2 * i + 1];
    a0 += f * src[0];
    a1 += f * src[1];
    a2 += f * src[2];
    u0 += du * src[0];
    u1 += du * src[1];
    u2 += du * src[2];
    v0 += dv * src[0];
    v1 += dv * src[1];
    v2 += dv * src[2];
  }
  a[0] = a0, a[1] = a1, a[2] = a2;
  u[0] = u0, u[1] = u1, u[2] = u2;
  v[0] = v0, v[1] = v1, v[2] = v2;
}

}  // namespace relight
