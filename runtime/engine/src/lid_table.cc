// (C, gamma) table lookup (see lid_table.h).
#include "lid_table.h"

#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

constexpr int kFractionBits = 16;

// Largest i with angles[i] * 2^16 <= pos (angles increasing, pos >= angles[0] * 2^16).
uint32_t Bracket(const int32_t* angles_q16, uint32_t n, int64_t pos) {
  uint32_t lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    const uint32_t mid = lo + (hi - lo) / 2;
    if (static_cast<int64_t>(angles_q16[mid]) * 65536 <= pos) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

// Fraction (Q.16, rounded) of pos between angles a and b (b > a), clamped to [0, 1].
int64_t Fraction(int32_t a_q16, int32_t b_q16, int64_t pos) {
  const int64_t a = static_cast<int64_t>(a_q16) * 65536, b = static_cast<int64_t>(b_q16) * 65536;
  if (pos <= a) return 0;
  if (pos >= b) return int64_t{1} << kFractionBits;
  // (pos - a) < 2^41: shifted by 16 stays below 2^57.
  const int64_t span = b - a;
  return (((pos - a) << kFractionBits) + span / 2) / span;
}

int64_t Lerp(int64_t a, int64_t b, int64_t t) {
  const Int128 step = (static_cast<Int128>(b) - a) * t;
  return RoundShiftSat64(static_cast<Int128>(a) + RoundShiftSat64(step, -kFractionBits), 0);
}

}  // namespace

int64_t LidTableIntensityQ16(const LidTableView& t, Bam c, Bam gamma) {
  if (t.planes < 2 || t.gammas < 1) return 0;
  // Degrees x 2^32: BAM x 360 (a full turn is 360 x 2^32).
  const int64_t g_pos = static_cast<int64_t>(gamma) * 360;
  const int64_t g_first = static_cast<int64_t>(t.gamma_deg_q16[0]) * 65536;
  const int64_t g_last = static_cast<int64_t>(t.gamma_deg_q16[t.gammas - 1]) * 65536;
  if (g_pos < g_first || g_pos > g_last) return 0;
  const int64_t c_pos = static_cast<int64_t>(c) * 360;
  const uint32_t p = Bracket(t.c_deg_q16, t.planes, c_pos);
  const int64_t fc = Fraction(t.c_deg_q16[p], t.c_deg_q16[p + 1], c_pos);
  uint32_t g = 0;
  int64_t fg = 0;
  if (t.gammas > 1) {
    g = Bracket(t.gamma_deg_q16, t.gammas, g_pos);
    if (g + 1 >= t.gammas) g = t.gammas - 2;
    fg = Fraction(t.gamma_deg_q16[g], t.gamma_deg_q16[g + 1], g_pos);
  }
  const int64_t* row0 = t.candela_q16 + static_cast<uint64_t>(p) * t.gammas;
  const int64_t* row1 = row0 + t.gammas;
  const int64_t a = t.gammas > 1 ? Lerp(row0[g], row0[g + 1], fg) : row0[0];
  const int64_t b = t.gammas > 1 ? Lerp(row1[g], row1[g + 1], fg) : row1[0];
  return Lerp(a, b, fc);
}

}  // namespace relight
