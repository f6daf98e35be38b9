// Receivers a beam cannot reach (see direct_cull.h).
#include "direct_cull.h"

#include <cstddef>
#include <limits>

#include "direct_aimed.h"
#include "relight/base/fixed_math.h"

namespace relight {

void PrepareDirectBlocks(const DirectPoint* points, uint32_t count, const GammaTable& gt,
                         std::vector<DirectBlock>* blocks) {
  blocks->assign((count + kDirectBlockPoints - 1) / kDirectBlockPoints, DirectBlock{{0, 0, 0}, kNoPoints});
  for (size_t b = 0; b < blocks->size(); ++b) {
    const uint32_t first = static_cast<uint32_t>(b) * kDirectBlockPoints;
    const uint32_t end = count - first < kDirectBlockPoints ? count : first + kDirectBlockPoints;
    int64_t sum[3] = {0, 0, 0};  // < 32 x 2^30 each
    bool any = false;
    for (uint32_t r = first; r < end; ++r) {
      if (points[r].geometry == 0) continue;  // lit by nothing: 0 whatever the aim
      any = true;
      for (int c = 0; c < 3; ++c) sum[c] += points[r].direction_q30[c];
    }
    DirectBlock& block = (*blocks)[b];
    if (!any) continue;
    if ((sum[0] | sum[1] | sum[2]) == 0) {  // directions that cancel: no useful cone
      block = DirectBlock{{0, 0, 0}, 0x80000000u};
      continue;
    }
    NormaliseQ30(sum, block.centre_q30);
    uint32_t half = 0;
    for (uint32_t r = first; r < end; ++r) {
      if (points[r].geometry == 0) continue;
      const int32_t* d = points[r].direction_q30;
      const int64_t cos_q60 = int64_t{d[0]} * block.centre_q30[0] + int64_t{d[1]} * block.centre_q30[1] +
                              int64_t{d[2]} * block.centre_q30[2];
      const Bam g = GammaFromCosQ60(gt, cos_q60);
      half = g > half ? g : half;
    }
    block.half_angle = half;
  }
}

uint64_t LidZeroFromBam(const int64_t* lid_q16, int M) {
  int last = -1;  // the last non-zero sample
  for (int k = 0; k <= M; ++k) {
    if (lid_q16[k] != 0) last = k;
  }
  if (last < 0) return 0;
  if (last == M) return uint64_t{1} << 32;
  // LidIntensityFastQ16: index = (gamma M + 2^14) >> 31; 0 once index >= last + 1
  // (both ends of the segment 0, or index >= M and sample M 0).
  const uint64_t need = (static_cast<uint64_t>(last + 1) << 31) - (uint64_t{1} << 14);
  return (need + static_cast<uint64_t>(M) - 1) / static_cast<uint64_t>(M);
}

int64_t ZeroCosQ60(const GammaTable& gt, uint64_t g_zero) {
  // GammaFromCosQ60 is non-increasing in cos, 2^31 at -2^62, 0 at 2^62.
  constexpr int64_t kLo = -(int64_t{1} << 62), kHi = int64_t{1} << 62;
  if (GammaFromCosQ60(gt, kLo) < g_zero) return std::numeric_limits<int64_t>::min();
  if (GammaFromCosQ60(gt, kHi) >= g_zero) return std::numeric_limits<int64_t>::max();
  int64_t lo = kLo, hi = kHi;  // Gamma(lo) >= g_zero > Gamma(hi)
  // hi - lo < 2^63 at every step but the first: halve in uint64.
  while (static_cast<uint64_t>(hi) - static_cast<uint64_t>(lo) > 1) {
    const int64_t mid = lo + static_cast<int64_t>((static_cast<uint64_t>(hi) - static_cast<uint64_t>(lo)) / 2);
    if (GammaFromCosQ60(gt, mid) >= g_zero) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

}  // namespace relight
