// The fixture frame in fixed point (bake.h, "The fixture frame"): from the
// mounting, yaw, pan, tilt and roll to three Q1.30 unit vectors, the beam
// axis and the C 0 / C 90 directions. Control rate: once per pan/tilt change.
// Integer-only, allocation-free, thread-safe. The baker's float64 mirror is
// baker/include/relight/baker/fixture_frame.h; tests hold the two together.
#pragma once

#include <cstdint>

#include "relight/bake/bake.h"
#include "relight/base/fixed.h"

namespace relight {

struct FixtureFrameQ30 {
  int32_t c0[3];    // C 0 at gamma 90
  int32_t c90[3];   // C 90 at gamma 90
  int32_t axis[3];  // gamma 0 (the beam)
};

struct FixturePoseQ16 {
  Mounting mounting = Mounting::kHanging;
  Q16_16 yaw_deg, pan_deg, tilt_deg, roll_deg;
};

// Sines and cosines from SinCosQ30 (2 LSB), products rounded once per step
// (Q2.60 -> Q1.30): each component within ~6 LSB of Q1.30 of the exact
// frame. For hanging and standing fixtures with yaw 0, `axis` is bit for bit
// BeamAxisQ30 (weights.h), so axisymmetric luminaires see no change.
void MakeFixtureFrameQ30(const FixturePoseQ16& pose, FixtureFrameQ30* frame);

// Pan and tilt (Q16.16 degrees) that put the beam axis on `target_q16`
// (Q16.16 metres) from `position_q16`: tilt in [0, 180], pan in (-180, 180],
// pan 0 when the target lies along the rest axis (the float64 AimAtPose in
// fixed point). Returns false (and leaves pan and tilt) when the two points
// coincide.
bool AimAtQ16(Mounting mounting, Q16_16 yaw_deg, const int32_t position_q16[3],
              const int32_t target_q16[3], Q16_16* pan_deg, Q16_16* tilt_deg);

}  // namespace relight
