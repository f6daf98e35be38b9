// Luminance to 8-bit sRGB through a table (see tone_map.h). Integer-only.
//
// The curve, with exposure x = L / white:
//   y = x (1 + x / 16) / (1 + x)      (Reinhard et al. 2002, Eq. 4, with the
//                                      burn-out point at x = 4: y(4) = 1)
// so white (x = 1) shows as y = 17/32 = 0.531 (sRGB code 193), highlights
// roll off softly up to 4x white, and everything above saturates to 255.
// y is then encoded with the sRGB transfer function and rounded to 8 bits.
#include "relight/engine/tone_map.h"

#include <cstddef>

#include "relight/base/fixed.h"

namespace relight {
namespace {

// Linear light (Q0.24) at which sRGB code c (1..255) begins, i.e. the
// decoded value of the half-way point between codes c-1 and c:
//   kSrgbThresholdQ24[c-1] = round(2^24 * decode((c - 0.5) / 255)),
//   decode(v) = v / 12.92 for v <= 0.04045, ((v + 0.055) / 1.055)^2.4 above
// (IEC 61966-2-1), computed offline in float64. A linear value maps to the
// code whose threshold it last reached, which rounds the encoded value to
// the nearest code.
constexpr int32_t kSrgbThresholdQ24[255] = {
    2546, 7639, 12731, 17823, 22916, 28008, 33100, 38193,
    43285, 48377, 53491, 58876, 64564, 70561, 76870, 83497,
    90446, 97721, 105327, 113267, 121545, 130167, 139134, 148452,
    158125, 168155, 178547, 189304, 200431, 211929, 223804, 236057,
    248694, 261716, 275128, 288932, 303133, 317732, 332733, 348140,
    363955, 380181, 396821, 413879, 431357, 449258, 467586, 486342,
    505529, 525152, 545211, 565711, 586653, 608041, 629876, 652163,
    674902, 698098, 721752, 745867, 770446, 795491, 821005, 846989,
    873447, 900381, 927793, 955687, 984063, 1012925, 1042274, 1072114,
    1102446, 1133273, 1164597, 1196421, 1228746, 1261575, 1294909, 1328752,
    1363106, 1397972, 1433353, 1469251, 1505667, 1542605, 1580066, 1618053,
    1656567, 1695611, 1735186, 1775295, 1815939, 1857121, 1898843, 1941107,
    1983914, 2027267, 2071167, 2115618, 2160619, 2206175, 2252285, 2298953,
    2346181, 2393969, 2442321, 2491237, 2540720, 2590772, 2641395, 2692589,
    2744358, 2796703, 2849626, 2903128, 2957212, 3011879, 3067131, 3122970,
    3179397, 3236415, 3294024, 3352228, 3411027, 3470423, 3530418, 3591014,
    3652213, 3714015, 3776424, 3839439, 3903064, 3967300, 4032148, 4097611,
    4163689, 4230385, 4297699, 4365635, 4434193, 4503374, 4573182, 4643616,
    4714680, 4786373, 4858699, 4931658, 5005252, 5079483, 5154353, 5229862,
    5306012, 5382805, 5460243, 5538327, 5617058, 5696438, 5776469, 5857152,
    5938488, 6020480, 6103128, 6186434, 6270400, 6355027, 6440316, 6526270,
    6612889, 6700175, 6788129, 6876753, 6966048, 7056016, 7146659, 7237977,
    7329972, 7422645, 7515998, 7610033, 7704750, 7800152, 7896239, 7993013,
    8090476, 8188628, 8287471, 8387007, 8487236, 8588161, 8689783, 8792102,
    8895121, 8998841, 9103263, 9208388, 9314218, 9420754, 9527997, 9635949,
    9744612, 9853986, 9964072, 10074873, 10186389, 10298622, 10411573, 10525243,
    10639634, 10754747, 10870583, 10987144, 11104431, 11222444, 11341186, 11460658,
    11580861, 11701795, 11823464, 11945867, 12069006, 12192883, 12317497, 12442852,
    12568948, 12695786, 12823368, 12951694, 13080766, 13210586, 13341154, 13472472,
    13604541, 13737361, 13870936, 14005264, 14140349, 14276191, 14412790, 14550150,
    14688269, 14827151, 14966796, 15107205, 15248379, 15390320, 15533028, 15676506,
    15820753, 15965772, 16111564, 16258129, 16405469, 16553585, 16702478,
};

constexpr int kYFracBits = 24;

// Number of thresholds <= y_q24 (binary search): the sRGB code of y.
uint8_t EncodeSrgb8(int64_t y_q24) {
  int lo = 0, hi = 255;  // answer in [lo, hi]
  while (lo < hi) {
    const int mid = (lo + hi + 1) / 2;
    if (kSrgbThresholdQ24[mid - 1] <= y_q24) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  return static_cast<uint8_t>(lo);
}

// y(x) in Q0.24 for luminance l and white w (both LightQ12, w > 0):
// y = l (16 w + l) / (16 w (w + l)), formed in 128 bits.
int64_t ShoulderQ24(int64_t l, int64_t w) {
  if (l <= 0) return 0;
  const UInt128 num = static_cast<UInt128>(l) * static_cast<UInt128>(16 * w + l) << kYFracBits;
  const UInt128 den = static_cast<UInt128>(16 * w) * static_cast<UInt128>(w + l);
  const UInt128 y = (num + den / 2) / den;
  constexpr UInt128 kOne = static_cast<UInt128>(1) << kYFracBits;
  return static_cast<int64_t>(y > kOne ? kOne : y);
}

}  // namespace

void BuildToneMap(int32_t white_q12, ToneMap* out) {
  const int64_t white = white_q12 > 0 ? white_q12 : 1;
  // Smallest shift whose last entry starts at or beyond 4x white, so that
  // entry (and every luminance clamped to it) is 255.
  int shift = 0;
  while (shift < 31 && (static_cast<int64_t>(kToneMapEntries - 1) << shift) < 4 * white) ++shift;
  out->white_q12 = static_cast<int32_t>(white);
  out->shift = shift;
  for (int i = 0; i < kToneMapEntries; ++i) {
    // Entry i covers [i, i + 1) << shift; its lower edge keeps 0 -> 0.
    const int64_t l = static_cast<int64_t>(i) << shift;
    out->table[i] = EncodeSrgb8(ShoulderQ24(l, white));
  }
  out->fine_shift = shift >= 4 ? shift - 4 : 0;
  for (int i = 0; i < kToneMapEntries; ++i) {
    out->fine[i] = EncodeSrgb8(ShoulderQ24(static_cast<int64_t>(i) << out->fine_shift, white));
  }
}

void ToneMapRgb8(const ToneMap& map, LuminanceView luminance, uint8_t* out) {
  const int32_t* rgb_q12 = luminance.raw();
  const size_t n = luminance.raw_size();
  for (size_t i = 0; i < n; ++i) {
    const int32_t l = rgb_q12[i] > 0 ? rgb_q12[i] : 0;
    const uint32_t fine_index = static_cast<uint32_t>(l) >> map.fine_shift;
    if (fine_index < kToneMapEntries) {
      out[i] = map.fine[fine_index];
      continue;
    }
    uint32_t index = static_cast<uint32_t>(l) >> map.shift;
    if (index > kToneMapEntries - 1) index = kToneMapEntries - 1;
    out[i] = map.table[index];
  }
}

}  // namespace relight
