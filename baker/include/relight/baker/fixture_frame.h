// Where a fixture's photometric frame points in the world (float64): the
// mounting (hanging, standing, wall), the base's yaw, pan, tilt and the roll
// about the beam axis. runtime/bake/include/relight/bake/bake.h defines the convention;
// the runtime mirrors it in fixed point (runtime/engine/src/fixture_frame.h) and the
// reference solve, the baker and the tests use this one.
#pragma once

#include "relight/baker/scene.h"

namespace relight::baker {

struct FixtureFrame {
  Vec3 c0{1, 0, 0};     // unit: direction of C 0 at gamma 90
  Vec3 c90{0, 1, 0};    // unit: direction of C 90 at gamma 90
  Vec3 axis{0, 0, -1};  // unit: beam axis, gamma 0
  // c0 x c90 = -axis: (c0, c90, -axis) is a right-handed frame.
};

struct FixturePose {
  MountingKind mounting = MountingKind::kHanging;
  double yaw_deg = 0, pan_deg = 0, tilt_deg = 0, roll_deg = 0;
};

FixtureFrame MakeFixtureFrame(const FixturePose& pose);
FixturePose PoseOf(const Luminaire& lum);  // the scene's defaults

// Photometric angles of unit world direction `dir`: C in [0, 360), gamma in [0, 180].
void PhotometricAngles(const FixtureFrame& frame, const Vec3& dir, double* c_deg,
                       double* gamma_deg);
// Intensity (cd) of `lid` in world direction `dir` (unit) for a fixture in `frame`.
double FrameIntensity(const Lid& lid, const FixtureFrame& frame, const Vec3& dir);

// Pan and tilt (degrees) that aim the beam at `target` from `position` for
// any mounting and yaw: tilt in [0, 180], pan in (-180, 180], pan 0 when the
// target lies along the rest axis. The roll does not move the axis.
void AimAtPose(MountingKind mounting, double yaw_deg, const Vec3& position, const Vec3& target,
               double* pan_deg, double* tilt_deg);

}  // namespace relight::baker
