// Random looks of a luminaire for the compression error (compression_looks.h).
#include "compression_looks.h"

#include <cmath>
#include <random>

#include "relight/baker/sh_rotation.h"

namespace relight::baker {

std::vector<Eigen::VectorXd> CompressionLooks(const Luminaire& lum, int degree, int count,
                                              uint32_t seed) {
  const std::vector<double> local = ProjectLidSh(lum.lid, degree);
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<Eigen::VectorXd> looks;
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
    looks.push_back(Eigen::Map<const Eigen::VectorXd>(world.data(), static_cast<Eigen::Index>(world.size())));
  }
  return looks;
}

}  // namespace relight::baker
