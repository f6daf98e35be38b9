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

void GatherLeafFromInner(const EmitterInnerSourceEntry* e, uint32_t count, const int32_t* rows, int64_t a[3],
                         int64_t m[3]) {
  int64_t a0 = 0, a1 = 0, a2 = 0, m0 = 0, m1 = 0, m2 = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const int32_t* row = &rows[kInnerRowInts * size_t{e[i].source}];
    const int64_t f = e[i].f, wu = e[i].wu, wv = e[i].wv;
    a0 += f * row[0];
    a1 += f * row[1];
    a2 += f * row[2];
    m0 += wu * row[4] + wv * row[8];
    m1 += wu * row[5] + wv * row[9];
    m2 += wu * row[6] + wv * row[10];
  }
  a[0] += a0, a[1] += a1, a[2] += a2;
  m[0] = m0, m[1] = m1, m[2] = m2;
}

void GatherInnerFromInner(const EmitterInnerSourceEntry* e, const int32_t* g, uint32_t count, const int32_t* rows,
                          int64_t a[3], int64_t u[3], int64_t v[3], int64_t m[3]) {
  int64_t a0 = 0, a1 = 0, a2 = 0, u0 = 0, u1 = 0, u2 = 0, v0 = 0, v1 = 0, v2 = 0, m0 = 0, m1 = 0, m2 = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const int32_t* row = &rows[kInnerRowInts * size_t{e[i].source}];
    const int64_t f = e[i].f, du = g[2 * i], dv = g[2 * i + 1], wu = e[i].wu, wv = e[i].wv;
    a0 += f * row[0];
    a1 += f * row[1];
    a2 += f * row[2];
    u0 += du * row[0];
    u1 += du * row[1];
    u2 += du * row[2];
    v0 += dv * row[0];
    v1 += dv * row[1];
    v2 += dv * row[2];
    m0 += wu * row[4] + wv * row[8];
    m1 += wu * row[5] + wv * row[9];
    m2 += wu * row[6] + wv * row[10];
  }
  a[0] += a0, a[1] += a1, a[2] += a2;
  u[0] += u0, u[1] += u1, u[2] += u2;
  v[0] += v0, v[1] += v1, v[2] += v2;
  m[0] = m0, m[1] = m1, m[2] = m2;
}

}  // namespace relight
