// The radiosity system per colour channel c (Dobashi Eq. 14, 16-17):
//   M = rho_c (E + F M)   <=>   (I - diag(rho_c) F) M = diag(rho_c) E
// with E the direct illuminance (lux) and M the exitance (lm/m^2) of each
// patch; luminance L = M / pi (cd/m^2). F is shared by every SH term and
// every luminaire, so each channel's matrix is LU-factorised once (channels
// with identical reflectances share a factorisation) and every right-hand
// side, all (N+1)^2 terms at once, reuses it.
// Thread safety: Solve*() are const and may run concurrently.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <vector>

#include "relight/baker/scene.h"

namespace relight::baker {

class RadiositySolver {
 public:
  // rho: per patch RGB reflectance; factorisations run on up to 2 threads.
  RadiositySolver(const Eigen::MatrixXd& form_factors, const std::vector<Rgb>& rho, int threads);

  // Solves (I - diag(rho_c) F) X = rhs, one column per right-hand side
  // (with rhs = an emitted exitance, X is the total exitance).
  Eigen::MatrixXd Solve(int channel, const Eigen::MatrixXd& rhs) const;
  // Exitance M (lm/m^2) from direct illuminance E (lux): rhs = diag(rho_c) E.
  Eigen::MatrixXd SolveExitance(int channel, const Eigen::MatrixXd& illuminance_lux) const;

  const Eigen::VectorXd& reflectance(int channel) const { return rho_[channel]; }
  int factorisations() const { return static_cast<int>(lu_.size()); }

 private:
  std::array<Eigen::VectorXd, 3> rho_;
  std::vector<Eigen::PartialPivLU<Eigen::MatrixXd>> lu_;
  std::array<int, 3> lu_of_channel_{};
};

}  // namespace relight::baker
