// Random looks of a luminaire for the compression error (compression_looks.h).
#include "compression_looks.h"

#include <cmath>
#include <random>

#include "relight/baker/sh_rotation.h"

namespace relight::baker {

std::vector<CompressionLook> CompressionLooks(const Luminaire& lum, int degree, int count,
                                              uint32_t seed) {
  const std::vector<double> local = ProjectLidSh(lum.lid, degree);
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<CompressionLook> looks;
  for (int i = 0; i < count; ++i) {
    // A unit quaternion of four normal deviates is uniform over rotations.
    double q[4], norm = 0;
    for (double& v : q) {
      v = normal(rng);
      norm += v * v;
    }
    norm = std::sqrt(norm);
    if (!(norm > 0)) norm = 1, q[0] = 1;
    const double w = q[0] / norm, x = q[1] / norm, y = q[2] / norm, z = q[3] / norm;
    const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    const std::vector<double> world = RotateSh(degree, ShRotationMatrices(degree, r), local);
    CompressionLook look;
    look.coef = Eigen::Map<const Eigen::VectorXd>(world.data(), static_cast<Eigen::Index>(world.size()));
    // The local frame (x, y, z) = (c0, c90, -axis) turned by r (world = r local).
    look.frame.c0 = {r[0][0], r[1][0], r[2][0]};
    look.frame.c90 = {r[0][1], r[1][1], r[2][1]};
    look.frame.axis = {-r[0][2], -r[1][2], -r[2][2]};
    looks.push_back(look);
  }
  return looks;
}

Eigen::MatrixXd DirectAtLook(const Lid& lid, const FixtureFrame& frame, const std::vector<Vec3>& direction,
                             const std::vector<double>& g_m2, const std::vector<Rgb>* rho) {
  const Eigen::Index n = static_cast<Eigen::Index>(direction.size());
  Eigen::MatrixXd out(n, 3);
  for (Eigen::Index v = 0; v < n; ++v) {
    const size_t i = static_cast<size_t>(v);
    const double e = g_m2[i] > 0 ? FrameIntensity(lid, frame, direction[i]) * g_m2[i] : 0.0;
    for (int c = 0; c < 3; ++c) out(v, c) = rho ? e * (*rho)[i][static_cast<size_t>(c)] / M_PI : e;
  }
  return out;
}

}  // namespace relight::baker
