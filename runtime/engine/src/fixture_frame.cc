// Fixture frames in fixed point (see fixture_frame.h and bake.h).
//
// Scaling: sines and cosines are Q1.30; a product of two is Q2.60 in int64
// (|.| <= 2^60) and is rounded back to Q1.30 once; the roll and yaw steps
// add two such products (|sum| <= 2^61) before rounding. Components stay
// within [-1, 1] plus a few LSB, far inside int32.
#include "fixture_frame.h"

#include "relight/base/fixed_math.h"
#include "relight/base/fixed_ops.h"

namespace relight {
namespace {

int32_t Mul30(int32_t a, int32_t b) {
  return SaturateI32(RoundShiftSat64(static_cast<Int128>(a) * b, -30));
}

// a * ca + b * cb, one rounding.
int32_t Mix30(int32_t a, int32_t ca, int32_t b, int32_t cb) {
  const Int128 s = static_cast<Int128>(a) * ca + static_cast<Int128>(b) * cb;
  return SaturateI32(RoundShiftSat64(s, -30));
}

void WallBase(int32_t v[3]) {
  const int32_t x = v[0], y = v[1], z = v[2];
  v[0] = -z;
  v[1] = -y;
  v[2] = -x;
}

void RotateAbout(const int32_t a[3], const int32_t b[3], int32_t c, int32_t s, int32_t out_a[3],
                 int32_t out_b[3]) {
  for (int i = 0; i < 3; ++i) {
    out_a[i] = Mix30(a[i], c, b[i], s);
    out_b[i] = Mix30(a[i], -s, b[i], c);
  }
}

}  // namespace

void MakeFixtureFrameQ30(const FixturePoseQ16& pose, FixtureFrameQ30* f) {
  Q1_30 sp, cp, st, ct;
  SinCosQ30(DegreesToBam(pose.pan_deg), &sp, &cp);
  SinCosQ30(DegreesToBam(pose.tilt_deg), &st, &ct);
  f->c0[0] = Mul30(ct.raw(), cp.raw());
  f->c0[1] = Mul30(ct.raw(), sp.raw());
  f->c0[2] = st.raw();
  f->c90[0] = -sp.raw();
  f->c90[1] = cp.raw();
  f->c90[2] = 0;
  f->axis[0] = Mul30(st.raw(), cp.raw());
  f->axis[1] = Mul30(st.raw(), sp.raw());
  f->axis[2] = -ct.raw();
  switch (pose.mounting) {
    case Mounting::kHanging:
      break;
    case Mounting::kStanding:
      f->c0[2] = -f->c0[2];
      f->c90[0] = -f->c90[0];
      f->c90[1] = -f->c90[1];
      f->axis[2] = -f->axis[2];
      break;
    case Mounting::kWall:
      WallBase(f->c0);
      WallBase(f->c90);
      WallBase(f->axis);
      break;
  }
  if (pose.roll_deg.raw() != 0) {
    Q1_30 sr, cr;
    SinCosQ30(DegreesToBam(pose.roll_deg), &sr, &cr);
    int32_t c0[3], c90[3];
    RotateAbout(f->c0, f->c90, cr.raw(), sr.raw(), c0, c90);
    for (int i = 0; i < 3; ++i) {
      f->c0[i] = c0[i];
      f->c90[i] = c90[i];
    }
  }
  if (pose.yaw_deg.raw() != 0) {
    Q1_30 sy, cy;
    SinCosQ30(DegreesToBam(pose.yaw_deg), &sy, &cy);
    for (int32_t* v : {f->c0, f->c90, f->axis}) {
      const int32_t x = v[0], y = v[1];
      v[0] = Mix30(x, cy.raw(), y, -sy.raw());
      v[1] = Mix30(x, sy.raw(), y, cy.raw());
    }
  }
}

bool AimAtQ16(Mounting mounting, Q16_16 yaw_deg, const int32_t position_q16[3],
              const int32_t target_q16[3], Q16_16* pan_deg, Q16_16* tilt_deg) {
  // Differences of Q16.16 metres: < 2^33, exact in int64.
  int64_t d[3];
  for (int i = 0; i < 3; ++i) d[i] = static_cast<int64_t>(target_q16[i]) - position_q16[i];
  if ((d[0] | d[1] | d[2]) == 0) return false;
  if (yaw_deg.raw() != 0) {
    // Undo the yaw: rotate by -yaw about z (Q33.16 x Q1.30, < 2^64 in 128 bits).
    Q1_30 sy, cy;
    SinCosQ30(DegreesToBam(yaw_deg), &sy, &cy);
    const Int128 x = static_cast<Int128>(d[0]) * cy.raw() + static_cast<Int128>(d[1]) * sy.raw();
    const Int128 y = -static_cast<Int128>(d[0]) * sy.raw() + static_cast<Int128>(d[1]) * cy.raw();
    // Keep 14 extra bits: the values stay < 2^50.
    d[0] = RoundShiftSat64(x, -16);
    d[1] = RoundShiftSat64(y, -16);
    d[2] *= int64_t{1} << 14;
  }
  if (mounting == Mounting::kStanding) d[2] = -d[2];
  if (mounting == Mounting::kWall) {
    const int64_t x = d[0];
    d[0] = -d[2];
    d[1] = -d[1];
    d[2] = -x;
  }
  // Scale up so the floor of the square root below costs < 2^-45 of the length.
  uint64_t largest = 0;
  for (int64_t v : d) {
    const uint64_t m = v < 0 ? 0 - static_cast<uint64_t>(v) : static_cast<uint64_t>(v);
    if (m > largest) largest = m;
  }
  while (largest < (uint64_t{1} << 45)) {
    largest <<= 1;
    for (int64_t& v : d) v *= 2;
  }
  const UInt128 h2 = static_cast<UInt128>(static_cast<Int128>(d[0]) * d[0]) +
                     static_cast<UInt128>(static_cast<Int128>(d[1]) * d[1]);
  const int64_t horizontal = static_cast<int64_t>(ISqrt128(h2));
  *tilt_deg = BamToDegrees(Atan2Bam(horizontal, -d[2]));
  if (horizontal == 0) {
    *pan_deg = Q16_16::FromInt(0);
  } else {
    *pan_deg = BamToDegrees(Atan2Bam(d[1], d[0]));
  }
  return true;
}

}  // namespace relight
