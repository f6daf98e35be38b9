// Fixed-point real-SH rotation (see relight/sh_rotation.h). The recurrence is
// for harmonics without the Condon-Shortley phase; relight's carry (-1)^m
// (sh_index.h), so band 1 is taken in that basis and every finished band is
// conjugated by the signs (-1)^(|m| + |n|).
#include "relight/engine/sh_rotation.h"

#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

// sqrt(num / den) in Q3.29, rounded to nearest; num / den < 16.
int32_t SqrtRatioQ29(uint64_t num, uint64_t den) {
  if (num == 0) return 0;
  // sqrt(num * 2^60 / den) is Q30; one more bit, then round to Q29.
  const UInt128 q = (static_cast<UInt128>(num) << 62) / den;  // Q62 ratio, < 2^66
  const uint64_t root = ISqrt128(q);                           // Q31
  return static_cast<int32_t>((root + 2) >> 2);
}

size_t TableIndex(int l, int m, int n) {
  return (ShRotationBandOffset(l) - 10 + static_cast<size_t>((m + l) * (2 * l + 1) + (n + l))) * 3;
}

struct Band {
  int32_t* data;
  int l;
  int32_t& at(int m, int n) const { return data[(m + l) * (2 * l + 1) + (n + l)]; }
};

// Ivanic & Ruedenberg's P in Q2.60.
int64_t P(int i, int l, int a, int b, const Band& r1, const Band& prev) {
  const auto mul = [](int32_t x, int32_t y) { return static_cast<int64_t>(x) * y; };
  if (b == l) return mul(r1.at(i, 1), prev.at(a, l - 1)) - mul(r1.at(i, -1), prev.at(a, -l + 1));
  if (b == -l) return mul(r1.at(i, 1), prev.at(a, -l + 1)) + mul(r1.at(i, -1), prev.at(a, l - 1));
  return mul(r1.at(i, 0), prev.at(a, b));
}

}  // namespace

void InitShRotationTables(ShRotationTables* tables) {
  for (int l = 2; l <= kMaxShDegree; ++l) {
    for (int m = -l; m <= l; ++m) {
      const int am = m < 0 ? -m : m;
      for (int n = -l; n <= l; ++n) {
        const uint64_t denom = (n == l || n == -l) ? uint64_t{2} * l * (2 * l - 1)
                                                   : static_cast<uint64_t>((l + n) * (l - n));
        int32_t* t = tables->uvw_q29 + TableIndex(l, m, n);
        t[0] = SqrtRatioQ29(static_cast<uint64_t>((l + m) * (l - m)), denom);
        // v = 1/2 sqrt((1 + d)(l + |m| - 1)(l + |m|) / denom) (1 - 2d), d = [m == 0];
        // times sqrt(2) when |m| = 1 (the V term's factor, folded in here).
        const uint64_t vk = (m == 0 ? 2u : 1u) * (am == 1 ? 2u : 1u);
        const int32_t v = SqrtRatioQ29(vk * static_cast<uint64_t>((l + am - 1) * (l + am)), 4 * denom);
        t[1] = m == 0 ? -v : v;
        // w = -1/2 sqrt((l - |m| - 1)(l - |m|) / denom) (1 - d).
        t[2] = m == 0 ? 0 : -SqrtRatioQ29(static_cast<uint64_t>((l - am - 1) * (l - am)), 4 * denom);
      }
    }
  }
}

void ShRotationMatricesQ30(const ShRotationTables& tables, int degree, const int32_t r_q30[3][3],
                           int32_t* d_q30) {
  d_q30[0] = int32_t{1} << 30;
  if (degree <= 0) return;
  const int axis_of[3] = {1, 2, 0};  // m = -1, 0, 1 <-> y, z, x
  const Band r1{d_q30 + ShRotationBandOffset(1), 1};
  for (int m = -1; m <= 1; ++m) {
    for (int n = -1; n <= 1; ++n) r1.at(m, n) = r_q30[axis_of[m + 1]][axis_of[n + 1]];
  }
  for (int l = 2; l <= degree; ++l) {
    const Band prev{d_q30 + ShRotationBandOffset(l - 1), l - 1};
    const Band cur{d_q30 + ShRotationBandOffset(l), l};
    for (int m = -l; m <= l; ++m) {
      for (int n = -l; n <= l; ++n) {
        const int32_t* t = tables.uvw_q29 + TableIndex(l, m, n);
        Int128 sum = 0;
        if (t[0] != 0) sum += static_cast<Int128>(t[0]) * P(0, l, m, n, r1, prev);
        if (t[1] != 0) {
          int64_t v;
          if (m == 0) {
            v = P(1, l, 1, n, r1, prev) + P(-1, l, -1, n, r1, prev);
          } else if (m == 1) {
            v = P(1, l, 0, n, r1, prev);
          } else if (m == -1) {
            v = P(-1, l, 0, n, r1, prev);
          } else if (m > 0) {
            v = P(1, l, m - 1, n, r1, prev) - P(-1, l, -m + 1, n, r1, prev);
          } else {
            v = P(1, l, m + 1, n, r1, prev) + P(-1, l, -m - 1, n, r1, prev);
          }
          sum += static_cast<Int128>(t[1]) * v;
        }
        if (t[2] != 0) {
          const int64_t w = m > 0 ? P(1, l, m + 1, n, r1, prev) + P(-1, l, -m - 1, n, r1, prev)
                                  : P(1, l, m - 1, n, r1, prev) - P(-1, l, -m + 1, n, r1, prev);
          sum += static_cast<Int128>(t[2]) * w;
        }
        // Q3.29 x Q2.60 = Q.89, to Q1.30.
        cur.at(m, n) = SaturateI32(RoundShiftSat64(sum, -59));
      }
    }
  }
  // Into relight's Condon-Shortley basis (band 1 too: it fed the recurrence as is).
  for (int l = 1; l <= degree; ++l) {
    const Band d{d_q30 + ShRotationBandOffset(l), l};
    for (int m = -l; m <= l; ++m) {
      for (int n = -l; n <= l; ++n) {
        if (((m < 0 ? -m : m) + (n < 0 ? -n : n)) % 2 != 0) d.at(m, n) = -d.at(m, n);
      }
    }
  }
}

void RotateShQ16(int degree, const int32_t* d_q30, const int64_t* in_q16, int64_t* out_q16) {
  for (int l = 0; l <= degree; ++l) {
    const int32_t* d = d_q30 + ShRotationBandOffset(l);
    const int w = 2 * l + 1;
    for (int m = -l; m <= l; ++m) {
      Int128 sum = 0;
      for (int n = -l; n <= l; ++n) {
        sum += static_cast<Int128>(d[(m + l) * w + (n + l)]) * in_q16[ShIndex(l, n)];
      }
      out_q16[ShIndex(l, m)] = RoundShiftSat64(sum, -30);
    }
  }
}

}  // namespace relight
