// RGBA -> RGB row copy. A 1280x720 frame is 0.9 M pixels; after every draw
// this copy runs on the frame's critical path. Measured on the 2-core
// machine (/tmp microbenchmark, hot source): 32-bit word shifts 1.35 ms a
// frame, a byte loop 0.84-1.0 ms, one SSSE3 shuffle per 4 pixels 0.18-0.26 ms.
#include "rgba_rows.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define RELIGHT_RGBA_ROWS_SSSE3 1
#elif defined(__aarch64__)
#include <arm_neon.h>
#define RELIGHT_RGBA_ROWS_NEON 1
#endif

namespace relight::render {
namespace {

#ifdef RELIGHT_RGBA_ROWS_SSSE3
// 16 bytes in (4 pixels), 12 bytes of RGB out. The 16-byte store writes 4
// bytes past those 12, which the next step overwrites; the loop stops while
// at least 2 more pixels (8 bytes of output room) follow, and the byte loop
// finishes the row, so nothing past the row's end is touched.
__attribute__((target("ssse3"))) size_t RowSsse3(const uint8_t* src, size_t pixels, uint8_t* dst) {
  const __m128i drop_alpha = _mm_setr_epi8(0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13, 14, -1, -1, -1, -1);
  size_t x = 0;
  for (; x + 6 <= pixels; x += 4) {
    const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + 4 * x));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(dst + 3 * x), _mm_shuffle_epi8(v, drop_alpha));
  }
  return x;
}

bool HasSsse3() {
  static const bool has = __builtin_cpu_supports("ssse3");
  return has;
}
#endif

#ifdef RELIGHT_RGBA_ROWS_NEON
// 16 pixels a step: vld4 splits the channels, vst3 interleaves three back.
size_t RowNeon(const uint8_t* src, size_t pixels, uint8_t* dst) {
  size_t x = 0;
  for (; x + 16 <= pixels; x += 16) {
    const uint8x16x4_t v = vld4q_u8(src + 4 * x);
    const uint8x16x3_t rgb = {{v.val[0], v.val[1], v.val[2]}};
    vst3q_u8(dst + 3 * x, rgb);
  }
  return x;
}
#endif

void Tail(const uint8_t* src, size_t from, size_t pixels, uint8_t* dst) {
  for (size_t x = from; x < pixels; ++x) {
    dst[3 * x + 0] = src[4 * x + 0];
    dst[3 * x + 1] = src[4 * x + 1];
    dst[3 * x + 2] = src[4 * x + 2];
  }
}

}  // namespace

void RgbaRowToRgbScalar(const uint8_t* src, size_t pixels, uint8_t* dst) {
  Tail(src, 0, pixels, dst);
}

void RgbaRowToRgb(const uint8_t* src, size_t pixels, uint8_t* dst) {
  size_t done = 0;
#if defined(RELIGHT_RGBA_ROWS_SSSE3)
  if (HasSsse3()) done = RowSsse3(src, pixels, dst);
#elif defined(RELIGHT_RGBA_ROWS_NEON)
  done = RowNeon(src, pixels, dst);
#endif
  Tail(src, done, pixels, dst);
}

}  // namespace relight::render
