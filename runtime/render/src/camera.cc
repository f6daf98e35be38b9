#include "camera.h"

#include <algorithm>
#include <cmath>

namespace relight {
namespace render {
namespace {

constexpr double kPi = 3.14159265358979323846;

double Dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void Cross(const double a[3], const double b[3], double out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

// Returns false (and leaves v alone) for a vector too short to normalise.
bool Normalise(double v[3]) {
  const double len = std::sqrt(Dot(v, v));
  if (!(len > 1e-12)) return false;
  for (int i = 0; i < 3; ++i) v[i] /= len;
  return true;
}

}  // namespace

CameraFrame MakeCameraFrame(const CameraView& view, double aspect, const SceneSphere& scene) {
  CameraFrame cam;
  for (int i = 0; i < 3; ++i) {
    cam.eye_m[i] = view.position[i];
    cam.forward[i] = static_cast<double>(view.target[i]) - view.position[i];
  }
  if (!Normalise(cam.forward)) {
    cam.forward[0] = 0;
    cam.forward[1] = 0;
    cam.forward[2] = -1;
  }
  // World +z up, unless the view is within ~2.6 degrees of vertical.
  double world_up[3] = {0, 0, 1};
  if (std::fabs(cam.forward[2]) > 0.999) {
    world_up[1] = 1;
    world_up[2] = 0;
  }
  Cross(cam.forward, world_up, cam.right);
  Normalise(cam.right);
  Cross(cam.right, cam.forward, cam.up);

  const double fov_deg = std::clamp(static_cast<double>(view.fov_y_deg), 1.0, 179.0);
  cam.tan_half_fov_y = std::tan(fov_deg * kPi / 360.0);
  cam.aspect = aspect > 0 ? aspect : 1.0;

  // Depth range: just enclose the scene sphere. From inside a room the near
  // plane is a fixed fraction of the far one, which keeps 24-bit depth to
  // well under a millimetre at room scale (error ~ z^2 / near * 2^-24).
  double to_centre[3];
  for (int i = 0; i < 3; ++i) to_centre[i] = scene.centre_m[i] - cam.eye_m[i];
  const double dist = std::sqrt(Dot(to_centre, to_centre));
  const double radius = std::max(scene.radius_m, 1e-3);
  cam.far_m = (dist + radius) * 1.01;
  cam.near_m = std::max((dist - radius) * 0.99, cam.far_m / 2000.0);
  return cam;
}

void ViewMatrix(const CameraFrame& cam, float out[16]) {
  // Rows: right, up, -forward; column 3: the eye moved to the origin.
  const double* rows[3] = {cam.right, cam.up, cam.forward};
  const double sign[3] = {1, 1, -1};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out[c * 4 + r] = static_cast<float>(sign[r] * rows[r][c]);
    out[12 + r] = static_cast<float>(-sign[r] * Dot(rows[r], cam.eye_m));
    out[r * 4 + 3] = 0;
  }
  out[15] = 1;
}

void ProjectionMatrix(const CameraFrame& cam, float out[16]) {
  const double f = 1.0 / cam.tan_half_fov_y;
  const double n = cam.near_m;
  const double fa = cam.far_m;
  for (int i = 0; i < 16; ++i) out[i] = 0;
  out[0] = static_cast<float>(f / cam.aspect);
  out[5] = static_cast<float>(f);
  out[10] = static_cast<float>((fa + n) / (n - fa));
  out[11] = -1;
  out[14] = static_cast<float>(2 * fa * n / (n - fa));
}

void UnprojectDepth(const CameraFrame& cam, int x, int y, int width, int height, double depth01,
                    double out_world_m[3]) {
  const double x_ndc = (x + 0.5) / width * 2 - 1;
  const double y_ndc = 1 - (y + 0.5) / height * 2;  // y counts rows from the top
  const double z_ndc = 2 * depth01 - 1;
  const double n = cam.near_m;
  const double f = cam.far_m;
  // Inverse of the perspective depth mapping: distance along the view axis.
  const double along_m = 2 * f * n / ((f + n) - z_ndc * (f - n));
  const double side_m = x_ndc * along_m * cam.tan_half_fov_y * cam.aspect;
  const double rise_m = y_ndc * along_m * cam.tan_half_fov_y;
  for (int i = 0; i < 3; ++i) {
    out_world_m[i] = cam.eye_m[i] + cam.right[i] * side_m + cam.up[i] * rise_m + cam.forward[i] * along_m;
  }
}

}  // namespace render
}  // namespace relight
