// The consistency rules of a luminaire's zoom (bake.h BakeZoom), shared by
// the writer and the reader like the rest of bake_check.h.
#include <cstdint>

#include "relight/bake/bake_check.h"
#include "relight/bake/bake_limits.h"
#include "relight/base/status.h"

namespace relight::bake_format {

std::string CheckZoom(const BakeZoom& zoom, const BakeLid& lid) {
  if (!zoom.present()) {
    if (zoom.min_deg != 0 || zoom.max_deg != 0 || zoom.default_deg != 0 || zoom.lumens != 0 ||
        zoom.profile_end != 0) {
      return "a luminaire without a zoom profile has no zoom angles, lumens or profile end";
    }
    return "";
  }
  if (!lid.axisymmetric()) return "zoom: only an axisymmetric LID (no C planes) can zoom";
  const size_t n = zoom.profile.size();
  if (n < kMinZoomProfileSamples || n > kMaxZoomProfileSamples) {
    return StrFormat("zoom profile has %zu samples, outside [%u, %u]", n, kMinZoomProfileSamples,
                     kMaxZoomProfileSamples);
  }
  if (zoom.min_deg <= 0 || zoom.max_deg >= kMaxZoomAngleRaw || zoom.min_deg > zoom.max_deg) {
    return StrFormat("zoom range %d .. %d (Q16.16 degrees) is not within (0, 180) with min <= max",
                     zoom.min_deg, zoom.max_deg);
  }
  if (zoom.default_deg < zoom.min_deg || zoom.default_deg > zoom.max_deg) {
    return StrFormat("zoom default %d (Q16.16 degrees) is outside the range %d .. %d",
                     zoom.default_deg, zoom.min_deg, zoom.max_deg);
  }
  if (zoom.lumens <= 0 || zoom.lumens > kMaxZoomLumensRaw) {
    return StrFormat("zoom lumens %lld (Q48.16 lm) is outside (0, 2^32 lm]",
                     static_cast<long long>(zoom.lumens));
  }
  if (zoom.profile_end <= kMinZoomProfileEndRaw || zoom.profile_end > kMaxZoomProfileEndRaw) {
    return StrFormat("zoom profile end %d (Q16.16) is outside (1, 64] half beam angles",
                     zoom.profile_end);
  }
  if (zoom.profile[0] != kZoomProfileOne) {
    return StrFormat("zoom profile sample 0 is %d, expected 2^30 (1.0)", zoom.profile[0]);
  }
  for (size_t k = 1; k < n; ++k) {
    if (zoom.profile[k] < 0 || zoom.profile[k] > zoom.profile[k - 1]) {
      return StrFormat("zoom profile sample %zu: %d is below 0 or above sample %zu", k,
                       zoom.profile[k], k - 1);
    }
  }
  return "";
}

}  // namespace relight::bake_format
