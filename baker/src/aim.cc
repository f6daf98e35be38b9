// Beam axis from pan/tilt and its inverse, with the mounting convention of
// runtime/bake/include/relight/bake/bake.h:
//   hanging:  axis = (sin t cos p, sin t sin p, -cos t)
//   standing: axis = (sin t cos p, sin t sin p, +cos t)
#include <cmath>

#include "relight/baker/fixture_frame.h"
#include "relight/baker/photometry.h"

namespace relight::baker {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;
constexpr double kRadToDeg = 180.0 / kPi;
// Below this horizontal fraction of the aim the pan is meaningless (the beam
// points straight along z) and AimAt reports pan 0.
constexpr double kVerticalTolerance = 1e-9;
}  // namespace

Vec3 BeamAxis(MountingKind mounting, double pan_deg, double tilt_deg) {
  if (mounting == MountingKind::kWall) {
    return MakeFixtureFrame(FixturePose{mounting, 0, pan_deg, tilt_deg, 0}).axis;
  }
  const double p = pan_deg * kDegToRad, t = tilt_deg * kDegToRad;
  const double vertical = mounting == MountingKind::kHanging ? -std::cos(t) : std::cos(t);
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), vertical};
}

void AimAt(MountingKind mounting, const Vec3& position, const Vec3& target, double* pan_deg,
           double* tilt_deg) {
  if (mounting == MountingKind::kWall) {
    AimAtPose(mounting, 0, position, target, pan_deg, tilt_deg);
    return;
  }
  const double dx = target[0] - position[0], dy = target[1] - position[1];
  const double dz = target[2] - position[2];
  const double horizontal = std::hypot(dx, dy);
  const double length = std::hypot(horizontal, dz);
  *pan_deg = 0.0;
  *tilt_deg = 0.0;
  if (!(length > 0.0)) return;  // no direction: leave the fixture at rest
  // The component along the rest axis is cos t; atan2 keeps t accurate near 0 and 180.
  const double along_rest = mounting == MountingKind::kHanging ? -dz : dz;
  *tilt_deg = std::atan2(horizontal, along_rest) * kRadToDeg;  // [0, 180]
  if (horizontal <= kVerticalTolerance * length) return;
  double pan = std::atan2(dy, dx) * kRadToDeg;  // [-180, 180]
  if (pan <= -180.0) pan = 180.0;               // keep pan in (-180, 180]
  *pan_deg = pan;
}

}  // namespace relight::baker
