// The looks a basis compression is measured at (compress_basis.h): the SH
// coefficients of a luminaire's LID, in the fixture frame (sh_rotation.h
// ProjectLidSh), turned to random orientations, uniform over rotations with
// a fixed seed so a bake is repeatable. A rotation keeps each band's norm,
// so every look has the luminaire's full intensity. With each look, the
// luminaire's exact direct light on the receivers, so the error can be
// measured against the peak of all its light, not just of its SH part.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "relight/baker/fixture_frame.h"
#include "relight/baker/scene.h"

namespace relight::baker {

struct CompressionLook {
  Eigen::VectorXd coef;  // (degree+1)^2 SH coefficients, candela, world frame
  FixtureFrame frame;    // the orientation they were turned to
};

std::vector<CompressionLook> CompressionLooks(const Luminaire& lum, int degree, int count,
                                              uint32_t seed);

// receivers x 3: I(direction) x g per receiver (lux), times rho / pi per
// channel when `rho` is given (luminance of a vertex), for the look's frame.
Eigen::MatrixXd DirectAtLook(const Lid& lid, const FixtureFrame& frame, const std::vector<Vec3>& direction,
                             const std::vector<double>& g_m2, const std::vector<Rgb>* rho);

}  // namespace relight::baker
