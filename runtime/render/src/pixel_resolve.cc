// Built with -ffp-contract=off (CMakeLists.txt): the table's weights are
// then the same bits on every target.
#include "pixel_resolve.h"

#include <cmath>
#include <cstdlib>
#include <cstring>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#endif

#include "visible_triangles.h"

namespace relight::render {

// Pixels are stored as the low three bytes of a 32-bit word.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "the resolve writes pixels little-endian");

namespace {

uint32_t LoadEntry(const uint8_t* p) {
  uint32_t v;
  std::memcpy(&v, p, sizeof(v));
  return v;
}

void StoreEntry(uint8_t* p, uint32_t v) { std::memcpy(p, &v, sizeof(v)); }

double Dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void Cross(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

// x clamped to [0, 1], and 0 for a NaN (so the integer cast after it is defined).
double Unit(double x) { return x > 0 ? (x < 1 ? x : 1) : 0; }

// Where the ray from the eye through pixel (x, y) meets a triangle's plane,
// as its second and third vertex's barycentric weights (Moller-Trumbore's u
// and v). The ray's direction is linear in the pixel, d = d0 + x dx + y dy,
// and u, v and the determinant are each d dotted with a vector fixed per
// triangle, so per triangle they are three linear functions of (x, y) and
// per pixel two products with the reciprocal of the third.
struct TrianglePlane {
  double u[3], v[3], det[3];  // constant, x and y coefficients

  TrianglePlane(const double eye[3], const double d0[3], const double dx[3], const double dy[3], const float* a,
                const float* b, const float* c) {
    double e1[3], e2[3], to_eye[3];
    for (int i = 0; i < 3; ++i) {
      e1[i] = static_cast<double>(b[i]) - a[i];
      e2[i] = static_cast<double>(c[i]) - a[i];
      to_eye[i] = eye[i] - a[i];
    }
    // det = e1 . (d x e2) = d . (e2 x e1); u = to_eye . (d x e2) / det =
    // d . (e2 x to_eye) / det; v = d . (to_eye x e1) / det.
    double n_det[3], n_u[3], n_v[3];
    Cross(e2, e1, n_det);
    Cross(e2, to_eye, n_u);
    Cross(to_eye, e1, n_v);
    const double* n[3] = {n_u, n_v, n_det};
    double* out[3] = {u, v, det};
    for (int k = 0; k < 3; ++k) {
      out[k][0] = Dot(d0, n[k]);
      out[k][1] = Dot(dx, n[k]);
      out[k][2] = Dot(dy, n[k]);
    }
  }

  // Weights (in 1/255) of the second and third vertex at pixel (x, y). A
  // triangle seen edge-on (no usable plane) gets its first vertex's colour.
  void Weights(double x, double y, uint32_t* w1, uint32_t* w2) const {
    *w1 = 0;
    *w2 = 0;
    const double d = det[0] + x * det[1] + y * det[2];
    if (!(std::fabs(d) > 1e-300)) return;
    // The pixel centre lies in the triangle (the rasteriser put it there); a
    // rounding step outside is brought back onto its edge.
    const double inv = 1.0 / d;  // one division for both
    double wu = Unit((u[0] + x * u[1] + y * u[2]) * inv);
    double wv = Unit((v[0] + x * v[1] + y * v[2]) * inv);
    if (wu + wv > 1.0) {
      const double sum = wu + wv;
      wu /= sum;
      wv /= sum;
    }
    *w1 = static_cast<uint32_t>(wu * kResolveWeightOne + 0.5);  // both >= 0: + 0.5 rounds
    *w2 = static_cast<uint32_t>(wv * kResolveWeightOne + 0.5);
    if (*w1 + *w2 > kResolveWeightOne) *w2 = kResolveWeightOne - *w1;
  }
};

}  // namespace

uint32_t NumberShownTriangles(const uint8_t* seen, uint32_t triangle_count, uint16_t* slot_of_triangle) {
  uint32_t shown = 0;
  for (uint32_t t = 0; t < triangle_count; ++t) {
    if (seen[t] != 0 && shown < kResolveMaxSlots) {
      slot_of_triangle[t] = static_cast<uint16_t>(shown++);
    } else {
      slot_of_triangle[t] = static_cast<uint16_t>(kResolveBackground);
    }
  }
  return shown;
}

void BuildPixelTable(const CameraFrame& camera, int width, int height, const float* positions_m,
                     const uint32_t* triangles, const uint16_t* slot_of_triangle, uint32_t triangle_count,
                     uint8_t* id_rgba_to_table) {
  // The ray through the centre of GL pixel (x, y) (rows from the bottom):
  // forward + right * side * x_ndc + up * tan * y_ndc, with
  // x_ndc = (x + 0.5) * 2 / width - 1, so d = d0 + x dx + y dy.
  const double side = camera.tan_half_fov_y * camera.aspect;
  const double tan_y = camera.tan_half_fov_y;
  double d0[3], dx[3], dy[3];
  for (int i = 0; i < 3; ++i) {
    dx[i] = camera.right[i] * (side * 2 / width);
    dy[i] = camera.up[i] * (tan_y * 2 / height);
    d0[i] = camera.forward[i] + camera.right[i] * (side * (1.0 / width - 1)) + camera.up[i] * (tan_y * (1.0 / height - 1));
  }
  // A row crosses a triangle in runs of pixels: its plane is set up once a run.
  uint32_t plane_of = kResolveBackground;
  TrianglePlane plane(camera.eye_m, d0, dx, dy, positions_m, positions_m, positions_m);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      uint8_t* px = id_rgba_to_table + (static_cast<size_t>(y) * width + x) * 4;
      const uint32_t code = TriangleCode(px);
      if (code == 0 || code > triangle_count || slot_of_triangle[code - 1] == kResolveBackground) {
        StoreEntry(px, kResolveBackground);
        continue;
      }
      const uint32_t t = code - 1;
      if (t != plane_of) {
        const uint32_t* v = triangles + size_t{3} * t;
        plane = TrianglePlane(camera.eye_m, d0, dx, dy, positions_m + size_t{3} * v[0],
                              positions_m + size_t{3} * v[1], positions_m + size_t{3} * v[2]);
        plane_of = t;
      }
      uint32_t w1, w2;
      plane.Weights(x, y, &w1, &w2);
      StoreEntry(px, slot_of_triangle[t] | w1 << 16 | w2 << 24);
    }
  }
}

void GatherSlotColours(const uint32_t* shown_indices, uint32_t slots, const uint8_t* vertex_rgb8,
                       uint64_t* slot_colours) {
  for (size_t i = 0; i < size_t{3} * slots; ++i) slot_colours[i] = SpreadRgb(vertex_rgb8 + size_t{3} * shown_indices[i]);
}

namespace {

// Three weights (bits 16-23 and 24-31 of the entry, the first the rest of
// 255) applied to a slot's spread colours, each channel rounded to a byte:
// returns r | g << 8 | b << 16.
inline uint32_t WeighPixel(uint32_t entry, const uint64_t* c) {
  constexpr uint64_t kHalf = 128 | 128ull << 16 | 128ull << 32;
  constexpr uint64_t kLowBytes = 0xFF | 0xFFull << 16 | 0xFFull << 32;
  const uint64_t w1 = (entry >> 16) & 0xFFu;
  const uint64_t w2 = entry >> 24;
  const uint64_t w0 = kResolveWeightOne - w1 - w2;
  // DivideBy255Rounded in every field at once; no field carries into the next
  // (each stays at most 255 * 255 + 128 + 254 < 2^16).
  uint64_t t = w0 * c[0] + w1 * c[1] + w2 * c[2] + kHalf;
  t = (t + ((t >> 8) & kLowBytes)) >> 8;
  return static_cast<uint32_t>((t & 0xFF) | ((t >> 8) & 0xFF00) | ((t >> 16) & 0xFF0000));
}

// One row, pixel at a time: the reference every other body matches.
void ResolveRowScalar(const uint8_t* row, size_t from, size_t to, const uint64_t* slot_colours, uint32_t grey,
                      bool range_ends_here, uint8_t* out) {
  for (size_t x = from; x < to; ++x) {
    const uint32_t e = LoadEntry(row + x * 4);
    const uint32_t slot = e & 0xFFFFu;
    const uint32_t rgb = slot == kResolveBackground ? grey : WeighPixel(e, slot_colours + size_t{3} * slot);
    // Four bytes written, three kept: the next pixel writes over the
    // fourth; a range's last pixel writes three.
    if (x + 1 < to || !range_ends_here) {
      std::memcpy(out + 3 * x, &rgb, 4);
    } else {
      const uint8_t last[3] = {static_cast<uint8_t>(rgb), static_cast<uint8_t>(rgb >> 8),
                               static_cast<uint8_t>(rgb >> 16)};
      std::memcpy(out + 3 * x, last, 3);
    }
  }
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define RELIGHT_RESOLVE_AVX2 1

// Four pixels a step in 16-bit lanes (a pixel's spread colour is its four
// lanes r, g, b, 0): the slot colours gathered, each weight broadcast over
// its pixel's lanes, the rounding division in every lane. The same integer
// steps as WeighPixel, so the same bytes. Returns the first pixel it left.
__attribute__((target("avx2"))) size_t ResolveRowAvx2(const uint8_t* row, size_t width,
                                                      const uint64_t* slot_colours, uint32_t grey,
                                                      bool range_ends_here, uint8_t* out) {
  const __m128i slot_mask = _mm_set1_epi32(0xFFFF);
  const __m128i background = _mm_set1_epi32(static_cast<int>(kResolveBackground));
  // Byte 2 (w1) and byte 3 (w2) of each pixel's entry into its four 16-bit lanes.
  const __m256i take_w1 = _mm256_setr_epi8(2, -1, 2, -1, 2, -1, 2, -1, 10, -1, 10, -1, 10, -1, 10, -1,
                                           2, -1, 2, -1, 2, -1, 2, -1, 10, -1, 10, -1, 10, -1, 10, -1);
  const __m256i take_w2 = _mm256_setr_epi8(3, -1, 3, -1, 3, -1, 3, -1, 11, -1, 11, -1, 11, -1, 11, -1,
                                           3, -1, 3, -1, 3, -1, 3, -1, 11, -1, 11, -1, 11, -1, 11, -1);
  // Packed bytes r g b 0 r g b 0 per 128-bit lane to r g b r g b.
  const __m128i to_rgb = _mm_setr_epi8(0, 1, 2, 4, 5, 6, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1);
  const __m256i one = _mm256_set1_epi16(static_cast<int16_t>(kResolveWeightOne));
  const __m256i half = _mm256_set1_epi16(128);
  const __m256i grey_lanes = _mm256_set1_epi64x(static_cast<long long>(SpreadRgb(reinterpret_cast<const uint8_t*>(&grey))));
  const long long* base = reinterpret_cast<const long long*>(slot_colours);
  // The last step writes 2 bytes past its 4 pixels: within the range unless
  // it ends there, so that row keeps its last pixel for the scalar body.
  const size_t end = range_ends_here ? (width > 0 ? width - 1 : 0) : width;
  size_t x = 0;
  for (; x + 4 <= end; x += 4) {
    const __m128i e = _mm_loadu_si128(reinterpret_cast<const __m128i*>(row + x * 4));
    const __m128i slot = _mm_and_si128(e, slot_mask);
    const __m128i is_background = _mm_cmpeq_epi32(slot, background);
    const __m128i index = _mm_andnot_si128(is_background, _mm_mullo_epi32(slot, _mm_set1_epi32(3)));
    const __m256i c0 = _mm256_i32gather_epi64(base, index, 8);
    const __m256i c1 = _mm256_i32gather_epi64(base + 1, index, 8);
    const __m256i c2 = _mm256_i32gather_epi64(base + 2, index, 8);
    const __m256i e64 = _mm256_cvtepu32_epi64(e);
    const __m256i w1 = _mm256_shuffle_epi8(e64, take_w1);
    const __m256i w2 = _mm256_shuffle_epi8(e64, take_w2);
    const __m256i w0 = _mm256_sub_epi16(_mm256_sub_epi16(one, w1), w2);
    __m256i t = _mm256_add_epi16(_mm256_mullo_epi16(c0, w0), _mm256_mullo_epi16(c1, w1));
    t = _mm256_add_epi16(_mm256_add_epi16(t, _mm256_mullo_epi16(c2, w2)), half);
    t = _mm256_srli_epi16(_mm256_add_epi16(t, _mm256_srli_epi16(t, 8)), 8);
    t = _mm256_blendv_epi8(t, grey_lanes, _mm256_cvtepi32_epi64(is_background));
    const __m256i bytes = _mm256_packus_epi16(t, t);  // per 128-bit lane: 2 pixels' r g b 0, twice
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 3 * x),
                     _mm_shuffle_epi8(_mm256_castsi256_si128(bytes), to_rgb));
    _mm_storel_epi64(reinterpret_cast<__m128i*>(out + 3 * x + 6),
                     _mm_shuffle_epi8(_mm256_extracti128_si256(bytes, 1), to_rgb));
  }
  return x;
}

bool UseAvx2() {
  static const bool use = __builtin_cpu_supports("avx2") && std::getenv("RELIGHT_FORCE_SCALAR") == nullptr;
  return use;
}
#endif

}  // namespace

void ResolvePixels(const uint8_t* table, int width, int height, const uint64_t* slot_colours, uint8_t background,
                   uint8_t* out_rgb8) {
  ResolveRowsWith(ResolveBody::kBest, table, width, height, 0, height, slot_colours, background, out_rgb8);
}

bool ResolveRowsWith(ResolveBody body, const uint8_t* table, int width, int height, int y_begin, int y_end,
                     const uint64_t* slot_colours, uint8_t background, uint8_t* out_rgb8) {
  bool avx2 = false;
#ifdef RELIGHT_RESOLVE_AVX2
  avx2 = body == ResolveBody::kAvx2 ? __builtin_cpu_supports("avx2") : body == ResolveBody::kBest && UseAvx2();
#endif
  if (body == ResolveBody::kAvx2 && !avx2) return false;
  const size_t w = static_cast<size_t>(width);
  const uint32_t grey = background | background << 8 | static_cast<uint32_t>(background) << 16;
  for (int y = y_begin < 0 ? 0 : y_begin; y < y_end && y < height; ++y) {
    const uint8_t* row = table + static_cast<size_t>(height - 1 - y) * w * 4;  // GL rows: bottom first
    uint8_t* out = out_rgb8 + static_cast<size_t>(y) * w * 3;
    // The range's last row writes nothing past its last pixel: the next row
    // may be another thread's, or past the frame.
    const bool range_ends_here = y + 1 == y_end;
    size_t x = 0;
#ifdef RELIGHT_RESOLVE_AVX2
    if (avx2) x = ResolveRowAvx2(row, w, slot_colours, grey, range_ends_here, out);
#endif
    ResolveRowScalar(row, x, w, slot_colours, grey, range_ends_here, out);
  }
  return true;
}

}  // namespace relight::render
