// Fixture frames (fixture_frame.h). In the base frame of a hanging fixture
// (pan about +z, beam down at rest, tilt towards +x of the panned frame):
//   c0   = (cos t cos p, cos t sin p, sin t)
//   c90  = (-sin p, cos p, 0)
//   axis = (sin t cos p, sin t sin p, -cos t)
// Standing mirrors z (pan stays counter-clockwise from above) and negates c90
// so the frame keeps its handedness; a wall base maps (x, y, z) to
// (-z, -y, -x) (beam along +x at rest, tilt towards -z). Then the roll turns
// c0 towards c90 about the axis, and the yaw turns everything about world z.
#include "relight/baker/fixture_frame.h"

#include <cmath>

#include "vec3_math.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

Vec3 RotateZ(const Vec3& v, double c, double s) {
  return {c * v[0] - s * v[1], s * v[0] + c * v[1], v[2]};
}

Vec3 WallBase(const Vec3& v) { return {-v[2], -v[1], -v[0]}; }

}  // namespace

FixtureFrame MakeFixtureFrame(const FixturePose& pose) {
  const double p = pose.pan_deg * kDeg, t = pose.tilt_deg * kDeg;
  const double cp = std::cos(p), sp = std::sin(p), ct = std::cos(t), st = std::sin(t);
  FixtureFrame f;
  f.c0 = {ct * cp, ct * sp, st};
  f.c90 = {-sp, cp, 0};
  f.axis = {st * cp, st * sp, -ct};
  switch (pose.mounting) {
    case MountingKind::kHanging:
      break;
    case MountingKind::kStanding:
      f.c0[2] = -f.c0[2];
      f.c90 = {-f.c90[0], -f.c90[1], 0};
      f.axis[2] = -f.axis[2];
      break;
    case MountingKind::kWall:
      f.c0 = WallBase(f.c0);
      f.c90 = WallBase(f.c90);
      f.axis = WallBase(f.axis);
      break;
  }
  const double r = pose.roll_deg * kDeg, cr = std::cos(r), sr = std::sin(r);
  const Vec3 c0 = Add(Scale(f.c0, cr), Scale(f.c90, sr));
  const Vec3 c90 = Add(Scale(f.c0, -sr), Scale(f.c90, cr));
  f.c0 = c0;
  f.c90 = c90;
  if (pose.yaw_deg != 0) {
    const double y = pose.yaw_deg * kDeg, cy = std::cos(y), sy = std::sin(y);
    f.c0 = RotateZ(f.c0, cy, sy);
    f.c90 = RotateZ(f.c90, cy, sy);
    f.axis = RotateZ(f.axis, cy, sy);
  }
  return f;
}

FixturePose PoseOf(const Luminaire& lum) {
  return FixturePose{lum.mounting, lum.yaw_deg, lum.pan_deg, lum.tilt_deg, lum.roll_deg};
}

void PhotometricAngles(const FixtureFrame& frame, const Vec3& dir, double* c_deg,
                       double* gamma_deg) {
  const double x = Dot(dir, frame.c0), y = Dot(dir, frame.c90), z = Dot(dir, frame.axis);
  *gamma_deg = std::atan2(std::hypot(x, y), z) / kDeg;
  double c = std::atan2(y, x) / kDeg;
  if (c < 0) c += 360.0;
  if (c >= 360.0) c -= 360.0;
  *c_deg = c;
}

double FrameIntensity(const Lid& lid, const FixtureFrame& frame, const Vec3& dir) {
  double c = 0, g = 0;
  PhotometricAngles(frame, dir, &c, &g);
  return lid.Evaluate(c, g);
}

void AimAtPose(MountingKind mounting, double yaw_deg, const Vec3& position, const Vec3& target,
               double* pan_deg, double* tilt_deg) {
  Vec3 d = Sub(target, position);
  const double y = -yaw_deg * kDeg;
  d = RotateZ(d, std::cos(y), std::sin(y));
  // Into the hanging base frame (standing keeps x, y: its pan is not mirrored).
  if (mounting == MountingKind::kStanding) d[2] = -d[2];
  if (mounting == MountingKind::kWall) d = WallBase(d);  // its own inverse
  *pan_deg = 0;
  *tilt_deg = 0;
  const double horizontal = std::hypot(d[0], d[1]);
  const double length = std::hypot(horizontal, d[2]);
  if (!(length > 0)) return;
  *tilt_deg = std::atan2(horizontal, -d[2]) / kDeg;
  if (horizontal <= 1e-9 * length) return;
  double pan = std::atan2(d[1], d[0]) / kDeg;
  if (pan <= -180.0) pan = 180.0;
  *pan_deg = pan;
}

}  // namespace relight::baker
