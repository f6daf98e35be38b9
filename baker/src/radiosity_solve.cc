#include "radiosity_solve.h"

#include <algorithm>

#include "parallel_for.h"

namespace relight::baker {

RadiositySolver::RadiositySolver(const Eigen::MatrixXd& form_factors, const std::vector<Rgb>& rho,
                                 int threads) {
  const Eigen::Index n = form_factors.rows();
  for (int c = 0; c < 3; ++c) {
    rho_[c].resize(n);
    for (Eigen::Index i = 0; i < n; ++i) rho_[c](i) = rho[static_cast<size_t>(i)][c];
  }
  // Grey scenes (the usual case) need one factorisation, not three.
  std::vector<int> distinct;
  for (int c = 0; c < 3; ++c) {
    int found = -1;
    for (size_t k = 0; k < distinct.size(); ++k)
      if (rho_[distinct[k]] == rho_[c]) found = static_cast<int>(k);
    if (found < 0) {
      distinct.push_back(c);
      found = static_cast<int>(distinct.size()) - 1;
    }
    lu_of_channel_[c] = found;
  }
  lu_.resize(distinct.size());
  ParallelFor(distinct.size(), std::min(2, ResolveThreads(threads)), [&](size_t k, int) {
    Eigen::MatrixXd a = -(rho_[distinct[k]].asDiagonal() * form_factors);
    a.diagonal().array() += 1.0;
    lu_[k].compute(a);
  });
}

Eigen::MatrixXd RadiositySolver::Solve(int channel, const Eigen::MatrixXd& rhs) const {
  return lu_[lu_of_channel_[channel]].solve(rhs);
}

Eigen::MatrixXd RadiositySolver::SolveExitance(int channel,
                                               const Eigen::MatrixXd& illuminance_lux) const {
  return Solve(channel, rho_[channel].asDiagonal() * illuminance_lux);
}

}  // namespace relight::baker
