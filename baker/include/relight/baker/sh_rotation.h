// Rotating a function on the sphere in real spherical harmonics (float64):
// the Ivanic-Ruedenberg recurrences (J. Phys. Chem. 1996, corrected 1998)
// build the rotation matrix of each band from the 3 x 3 rotation, and the
// SH projection of a (C, gamma) LID in the fixture frame (bake.h) gives the
// coefficients they rotate. The runtime mirrors the rotation in fixed point
// (runtime/engine/include/relight/engine/sh_rotation.h).
#pragma once

#include <cstddef>
#include <vector>

#include "relight/baker/scene.h"
#include "relight/base/sh_index.h"  // ShRotationBandOffset

namespace relight::baker {

using relight::ShRotationBandOffset;

// For the rotation R (row-major, world = R local; its columns are the local
// axes in world coordinates), the band matrices D^l, l = 0..degree, each
// (2l+1)^2 values row-major [m + l][n + l], such that a function with local
// coefficients c has world coefficients
//   c'_lm = sum_n D^l_mn c_ln,   f_world(d) = f_local(R^T d).
std::vector<double> ShRotationMatrices(int degree, const double r[3][3]);
// c' = D c, band by band; `coef` has (degree+1)^2 values in ShIndex order.
std::vector<double> RotateSh(int degree, const std::vector<double>& bands,
                             const std::vector<double>& coef);

// SH coefficients (ShIndex order) of `lid` in the fixture frame
// (x, y, z) = (c0, c90, -axis): c_t = integral of I(C, gamma) Y_t over the
// sphere, by rings of gamma (Simpson, 0.125 degree steps) and a Fourier sum
// over C (0.5 degree midpoints). Axisymmetric lids give zonal coefficients.
std::vector<double> ProjectLidSh(const Lid& lid, int degree);

}  // namespace relight::baker
