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

namespace {

// Links from inner sources, with (an inner receiver) or without the
// gradient sums: one body, so the two paths cannot drift apart.
template <bool kGradients>
void FromInner(const EmitterInnerSourceEntry* e, const int32_t* g, uint32_t count, const int32_t* rows, int64_t a[3],
               int64_t u[3], int64_t v[3], int64_t m[3]) {
  int64_t sa[3] = {0, 0, 0}, su[3] = {0, 0, 0}, sv[3] = {0, 0, 0}, sm[3] = {0, 0, 0};
  for (uint32_t i = 0; i < count; ++i) {
    const int32_t* row = &rows[kInnerRowInts * size_t{e[i].source}];
    const int64_t f = e[i].f, wu = e[i].wu, wv = e[i].wv;
    for (int c = 0; c < 3; ++c) {
      sa[c] += f * row[c];
      sm[c] += wu * row[4 + c] + wv * row[8 + c];
      if constexpr (kGradients) {
        su[c] += int64_t{g[2 * size_t{i}]} * row[c];
        sv[c] += int64_t{g[2 * size_t{i} + 1]} * row[c];
      }
    }
  }
  for (int c = 0; c < 3; ++c) {
    a[c] += sa[c];
    m[c] = sm[c];
    if constexpr (kGradients) {
      u[c] += su[c];
      v[c] += sv[c];
    }
  }
}

}  // namespace

void GatherLeafFromInner(const EmitterInnerSourceEntry* e, uint32_t count, const int32_t* rows, int64_t a[3],
                         int64_t m[3]) {
  FromInner<false>(e, nullptr, count, rows, a, nullptr, nullptr, m);
}

void GatherInnerFromInner(const EmitterInnerSourceEntry* e, const int32_t* g, uint32_t count, const int32_t* rows,
                          int64_t a[3], int64_t u[3], int64_t v[3], int64_t m[3]) {
  FromInner<true>(e, g, count, rows, a, u, v, m);
}

}  // namespace relight
