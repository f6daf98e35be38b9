// Camera maths for the renderer: a look-at frame, GL matrices and the inverse
// mapping from a pixel plus its depth-buffer value back to a world point.
// Doubles here (the GL side of the fence); GL gets floats at the last step.
#pragma once

#include "relight/render/osmesa_frame.h"

namespace relight {
namespace render {

// A sphere around the mesh, used to fit the depth range to the scene.
struct SceneSphere {
  double centre_m[3] = {0, 0, 0};
  double radius_m = 1;
};

// An orthonormal camera frame with its projection parameters.
struct CameraFrame {
  double eye_m[3] = {0, 0, 0};
  double right[3] = {1, 0, 0};
  double up[3] = {0, 1, 0};
  double forward[3] = {0, 0, -1};
  double tan_half_fov_y = 0;
  double aspect = 1;  // width / height
  double near_m = 0.01;
  double far_m = 100;
};

// Up is world +z (rooms stand on z = 0); when the view is (nearly) vertical
// +y is used instead. A degenerate view (target == position) looks down -z.
// Near/far enclose `scene` as seen from the eye.
CameraFrame MakeCameraFrame(const CameraView& view, double aspect, const SceneSphere& scene);

// Column-major 4x4 matrices for glLoadMatrixf.
void ViewMatrix(const CameraFrame& cam, float out[16]);
void ProjectionMatrix(const CameraFrame& cam, float out[16]);

// World point under the centre of pixel (x, y) (top row first) at window depth
// `depth01` in [0, 1] (0 = near plane, 1 = far plane).
void UnprojectDepth(const CameraFrame& cam, int x, int y, int width, int height, double depth01,
                    double out_world_m[3]);

}  // namespace render
}  // namespace relight
