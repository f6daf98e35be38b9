// The float64 basis of one luminaire (Dobashi Eq. 15-17): for every SH term
// t of its degree N, the scene lit by a point source of intensity Y_t(r)
// candela, on every receiver set (set 0 = mesh vertices in cd/m^2, set k >= 1
// = grid k-1 in lux). Baker::Bake() quantises it; tests use it directly.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

#include "baker_core.h"

namespace relight::baker {

struct ReceiverBasis {
  // Per channel: receivers x (N+1)^2, per candela of Y_t.
  std::array<Eigen::MatrixXd, 3> basis;
  // Exact direct term per receiver (DirectModeKind::kExact only, else empty).
  std::vector<DirectGeometry> direct;
};

struct LuminaireBasis {
  int degree = 0;
  DirectModeKind mode = DirectModeKind::kExact;
  std::vector<ReceiverBasis> sets;  // vertices, then each grid
};

// The mode a luminaire is baked in: options.direct_mode when set, else exact.
DirectModeKind EffectiveDirectMode(const BakerCore& core);

// kExact: vertex basis = area-weighted average of the indirect luminance
// (M - rho E) / pi over adjacent patches; grid basis = gathered indirect
// illuminance sum_j G(p, j) M_j; plus the direct geometry per receiver.
// kAllInSh (Dobashi's original): vertex basis = average of M / pi; grid
// basis = gathered indirect + direct G Y_t at the point.
LuminaireBasis ComputeLuminaireBasis(const BakerCore& core, size_t luminaire, DirectModeKind mode);

}  // namespace relight::baker
