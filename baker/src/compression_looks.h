// The looks a basis compression is measured at (compress_basis.h): the SH
// coefficients of a luminaire's LID, in the fixture frame (sh_rotation.h
// ProjectLidSh), turned to random orientations, uniform over rotations with
// a fixed seed so a bake is repeatable. A rotation keeps each band's norm,
// so every look has the luminaire's full intensity.
#pragma once

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "relight/baker/scene.h"

namespace relight::baker {

std::vector<Eigen::VectorXd> CompressionLooks(const Luminaire& lum, int degree, int count,
                                              uint32_t seed);

}  // namespace relight::baker
