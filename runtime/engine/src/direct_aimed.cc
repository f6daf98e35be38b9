// The aimed direct term (see direct_aimed.h).
#include "direct_aimed.h"
#include "direct_aimed_simd.h"

#include <algorithm>

#include <cstddef>

#include "relight/bake/bake_limits.h"
#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

constexpr int kMaxShift = 90;                            // I x g < 2^79: 0 past this
constexpr uint64_t kMaxLuxQ12 = (uint64_t{1} << 33) - 1;  // 2^21 lux

static_assert(bake_format::kMaxCandelaRaw <= (int64_t{1} << 47),
              "LidIntensityFastQ16 and the E product assume candela <= 2^47");

int BitLength(UInt128 v) {
  int n = 0;
  while (v != 0) {
    v >>= 1;
    ++n;
  }
  return n;
}

}  // namespace

void PrepareDirectPoints(const DirectReceivers& rx, DirectPoints* out) {
  // Every receiver's point first (the blocks' cones need them), then only
  // the blocks that have any are kept, in a vector of their exact size: one
  // allocation that stays, so the heap keeps no hole per luminaire.
  std::vector<DirectPoint> all(rx.count, DirectPoint{{0, 0, 0}, 0});
  const int64_t mantissa = rx.geometry_scale.mantissa > 0 ? rx.geometry_scale.mantissa : 0;
  uint32_t g_max = 0;
  for (uint32_t r = 0; r < rx.count; ++r) g_max = rx.geometry[r] > g_max ? rx.geometry[r] : g_max;
  // g x m x 2^(exp - 34 + shift) < 2^32 for the largest g.
  const UInt128 p_max = static_cast<UInt128>(g_max) * static_cast<uint64_t>(mantissa);
  int shift = 32 - BitLength(p_max) + 34 - rx.geometry_scale.exponent;
  shift = shift < 0 ? 0 : (shift > kMaxShift ? kMaxShift : shift);
  out->shift = shift;
  const int64_t s = static_cast<int64_t>(rx.geometry_scale.exponent) - 34 + shift;
  for (uint32_t r = 0; r < rx.count; ++r) {
    const int16_t* d = rx.direction_q14 + static_cast<size_t>(r) * 3;
    if (rx.geometry[r] == 0 || mantissa == 0 || (d[0] | d[1] | d[2]) == 0) continue;
    DirectPoint& p = all[r];
    const int64_t v[3] = {d[0], d[1], d[2]};
    NormaliseQ30(v, p.direction_q30);
    const int64_t g = RoundShiftSat64(static_cast<Int128>(rx.geometry[r]) * mantissa, s);
    p.geometry = g > 0xffffffffLL ? 0xffffffffu : static_cast<uint32_t>(g);
  }
  PrepareDirectBlocks(all.data(), rx.count, SharedGammaTable(), &out->blocks);
  out->count = rx.count;
  out->block_points.assign(out->blocks.size(), 0);
  size_t kept = 0;
  for (size_t b = 0; b < out->blocks.size(); ++b) {
    out->block_points[b] = static_cast<uint32_t>(kept);
    if (out->blocks[b].half_angle == kNoPoints) continue;
    kept += std::min<size_t>(kDirectBlockPoints, rx.count - b * kDirectBlockPoints);
  }
  std::vector<DirectPoint>().swap(out->points);
  out->points.reserve(kept);
  for (size_t b = 0; b < out->blocks.size(); ++b) {
    if (out->blocks[b].half_angle == kNoPoints) continue;
    const size_t first = b * kDirectBlockPoints;
    const size_t end = std::min<size_t>(rx.count, first + kDirectBlockPoints);
    out->points.insert(out->points.end(), all.begin() + static_cast<std::ptrdiff_t>(first),
                       all.begin() + static_cast<std::ptrdiff_t>(end));
  }
}

int64_t LidIntensityFastQ16(const int64_t* candela_q16, int M, Bam gamma) {
  // As LidIntensityQ16: position gamma M / 2^31 in Q.16, rounded.
  constexpr int kDrop = 31 - 16;
  const uint64_t pos = (static_cast<uint64_t>(gamma) * static_cast<uint64_t>(M) +
                        (uint64_t{1} << (kDrop - 1))) >> kDrop;
  const uint64_t index = pos >> 16;
  if (index >= static_cast<uint64_t>(M)) return candela_q16[M];
  const int64_t fraction = static_cast<int64_t>(pos & 0xffff);
  const int64_t a = candela_q16[index];
  const int64_t step = (candela_q16[index + 1] - a) * fraction;  // |.| < 2^63
  // Rounded halves up, as RoundShiftSat64 (an arithmetic shift floors).
  return a + ((step + (int64_t{1} << 15)) >> 16);
}

namespace {

using AimedCall = DirectAimedCall;  // the per-call constants (direct_aimed_simd.h)

// E in Q.12 lux at one point, saturated to kMaxLuxQ12.
inline uint64_t PointLuxQ12(const DirectPoint& pt, const AimedCall& k, const GammaTable& gt,
                            const int64_t* lid_q16, int lid_m) {
  const int64_t cos_q60 = pt.direction_q30[0] * k.a0 + pt.direction_q30[1] * k.a1 + pt.direction_q30[2] * k.a2;
  if (cos_q60 <= k.zero_cos_q60) return 0;  // past the cut-off: I = 0
  const Bam gamma = GammaFromCosQ60(gt, cos_q60);
  const int64_t intensity_q16 = LidIntensityFastQ16(lid_q16, lid_m, gamma);
  // < 2^31 x 2^32: the product fits uint64.
  const uint64_t i = static_cast<uint64_t>((intensity_q16 + k.intensity_half) >> k.intensity_shift);
  const uint64_t p = i * pt.geometry;
  if (k.e_shift < 0) {  // geometry past any real scene: saturate rather than wrap
    const int up = -k.e_shift;
    return up >= 33 || p > (kMaxLuxQ12 >> up) ? (p == 0 ? 0 : kMaxLuxQ12) : p << up;
  }
  if (k.e_shift > 63) return 0;  // p < 2^63: below half an LSB
  const uint64_t e_q12 = (p + k.e_half) >> k.e_shift;  // half <= 2^62: no carry out
  return e_q12 > kMaxLuxQ12 ? kMaxLuxQ12 : e_q12;
}

template <bool kLuminance, bool kAddTo>
void AimedRange(const DirectPoint* block, uint32_t first, uint32_t end, const AimedCall& k,
                const GammaTable& gt, const int64_t* lid_q16, int lid_m, const uint32_t* rho_q32,
                int32_t* out) {
  for (uint32_t r = first; r < end; ++r) {
    const DirectPoint& pt = block[r - first];  // the block's points start at its first receiver
    const uint64_t e_q12 = pt.geometry != 0 ? PointLuxQ12(pt, k, gt, lid_q16, lid_m) : 0;
    int32_t* dst = out + static_cast<size_t>(r) * 3;
    if (kAddTo && e_q12 == 0) continue;  // + 0 leaves dst as it is
    for (int c = 0; c < 3; ++c) {
      uint64_t v = e_q12;
      // Q.12 lux (< 2^33) x Q0.32 (< 2^31) < 2^64, rounded to Q12 cd/m^2.
      if (kLuminance) v = (e_q12 * rho_q32[static_cast<size_t>(r) * 3 + c] + (uint64_t{1} << 31)) >> 32;
      int64_t value = v > 0x7fffffffu ? 0x7fffffff : static_cast<int64_t>(v);
      if (kAddTo) {
        value += dst[c];  // value >= 0, so only the top can be passed
        value = value > 0x7fffffff ? 0x7fffffff : value;
      }
      dst[c] = static_cast<int32_t>(value);
    }
  }
}

template <bool kLuminance, bool kAddTo>
uint32_t AimedLoop(const DirectPoints& points, const AimedCall& k, const GammaTable& gt,
               const int64_t* lid_q16, int lid_m, uint64_t g_zero, const uint32_t* rho_q32,
               int32_t* out) {
  const bool fits = DirectAimedVectorFits(k, lid_q16, lid_m);
  const bool wide = fits && DirectAimedHasAvx512(), vector = fits && DirectAimedHasAvx2();
  uint32_t vector_done = 0;
  const uint32_t count = points.count;
  const int32_t axis[3] = {static_cast<int32_t>(k.a0), static_cast<int32_t>(k.a1), static_cast<int32_t>(k.a2)};
  for (size_t b = 0; b < points.blocks.size(); ++b) {
    const uint32_t first = static_cast<uint32_t>(b) * kDirectBlockPoints;
    const uint32_t end = count - first < kDirectBlockPoints ? count : first + kDirectBlockPoints;
    if (BlockOutsideBeam(points.blocks[b], gt, axis, g_zero)) {
      if (!kAddTo) {  // every receiver's value is 0
        for (size_t i = static_cast<size_t>(first) * 3; i < static_cast<size_t>(end) * 3; ++i) out[i] = 0;
      }
      continue;
    }
    const DirectPoint* block = points.points.data() + points.block_points[b];
    // The same values, eight or four receivers a step, the rest scalar.
    const uint32_t* rho = kLuminance ? rho_q32 + static_cast<size_t>(first) * 3 : nullptr;
    int32_t* dst = out + static_cast<size_t>(first) * 3;
    const uint32_t done = wide     ? DirectAimedRangeAvx512(block, end - first, k, gt, lid_q16, lid_m, rho, kAddTo, dst)
                          : vector ? DirectAimedRangeAvx2(block, end - first, k, gt, lid_q16, lid_m, rho, kAddTo, dst)
                                   : 0;
    vector_done += done;
    AimedRange<kLuminance, kAddTo>(block + done, first + done, end, k, gt, lid_q16, lid_m, rho_q32, out);
  }
  return vector_done;
}

}  // namespace

uint32_t DirectLightAimedQ12(const DirectPoints& points, const GammaTable& gamma_table,
                             const int32_t axis_q30[3], const int64_t* lid_q16, int lid_m,
                             const uint32_t* reflectance_over_pi_q32, DirectStore store, int32_t* out) {
  AimedCall k;
  k.a0 = axis_q30[0];
  k.a1 = axis_q30[1];
  k.a2 = axis_q30[2];
  // The LID's own scale: its largest sample to 31 bits (O(M) per call, so a
  // zoom or beam edit needs nothing more); the lookup interpolates between
  // samples, so no value exceeds the largest.
  int64_t peak = 0;
  for (int i = 0; i <= lid_m; ++i) peak = lid_q16[i] > peak ? lid_q16[i] : peak;
  int bits = 0;
  while (bits < 63 && (peak >> bits) != 0) ++bits;
  k.intensity_shift = bits > 31 ? bits - 31 : 0;
  k.intensity_half = k.intensity_shift > 0 ? int64_t{1} << (k.intensity_shift - 1) : 0;
  k.e_shift = points.shift - k.intensity_shift;
  k.e_half = k.e_shift > 0 && k.e_shift <= 63 ? uint64_t{1} << (k.e_shift - 1) : 0;
  const GammaTable& gt = gamma_table;
  const uint64_t g_zero = LidZeroFromBam(lid_q16, lid_m);
  k.zero_cos_q60 = ZeroCosQ60(gt, g_zero);
  const uint32_t* rho = reflectance_over_pi_q32;
  if (rho != nullptr) {
    return store == DirectStore::kAdd ? AimedLoop<true, true>(points, k, gt, lid_q16, lid_m, g_zero, rho, out)
                                      : AimedLoop<true, false>(points, k, gt, lid_q16, lid_m, g_zero, rho, out);
  }
  return store == DirectStore::kAdd ? AimedLoop<false, true>(points, k, gt, lid_q16, lid_m, g_zero, nullptr, out)
                                    : AimedLoop<false, false>(points, k, gt, lid_q16, lid_m, g_zero, nullptr, out);
}

}  // namespace relight
