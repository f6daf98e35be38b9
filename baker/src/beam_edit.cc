#include "relight/baker/beam_edit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace relight::baker {

ControlPoint ParseControlPoint(const std::string& text) {
  ControlPoint p;
  const size_t eq = text.find('=');
  if (eq == std::string::npos) {
    throw std::invalid_argument("control point '" + text + "': expected GAMMA=CD or C:GAMMA=CD");
  }
  std::string left = text.substr(0, eq);
  try {
    const size_t colon = left.find(':');
    if (colon != std::string::npos) {
      p.c_deg = std::stod(left.substr(0, colon));
      left = left.substr(colon + 1);
    }
    size_t used = 0;
    p.gamma_deg = std::stod(left, &used);
    if (used != left.size()) throw std::invalid_argument("trailing text");
    const std::string right = text.substr(eq + 1);
    p.candela = std::stod(right, &used);
    if (used != right.size()) throw std::invalid_argument("trailing text");
  } catch (const std::exception&) {
    throw std::invalid_argument("control point '" + text + "': expected GAMMA=CD or C:GAMMA=CD "
                                "(degrees and candela as numbers)");
  }
  return p;
}

void ApplyControlPoint(const ControlPoint& p, PhotometricTable* t) {
  if (!(p.gamma_deg >= 0 && p.gamma_deg <= 180)) {
    throw std::invalid_argument("control point gamma must be in [0, 180] degrees");
  }
  if (!(p.candela >= 0) || !std::isfinite(p.candela)) {
    throw std::invalid_argument("control point candela must be >= 0");
  }
  size_t plane_only = t->planes();
  if (p.c_deg) {
    for (size_t i = 0; i < t->planes(); ++i) {
      if (std::abs(t->c_deg[i] - *p.c_deg) < 1e-9) plane_only = i;
    }
    if (plane_only == t->planes()) {
      throw std::invalid_argument("control point: C " + std::to_string(*p.c_deg) +
                                  " is not a plane the file stores");
    }
  }
  auto it = std::lower_bound(t->gamma_deg.begin(), t->gamma_deg.end(), p.gamma_deg - 1e-9);
  size_t g = static_cast<size_t>(it - t->gamma_deg.begin());
  if (it == t->gamma_deg.end() || std::abs(*it - p.gamma_deg) > 1e-9) {
    // A new knot: every plane takes its current value there.
    std::vector<double> values;
    for (size_t i = 0; i < t->planes(); ++i) {
      values.push_back(p.gamma_deg < t->gamma_deg.front() || p.gamma_deg > t->gamma_deg.back()
                           ? 0.0
                           : t->Evaluate(t->c_deg[i], p.gamma_deg));
    }
    const size_t old_gammas = t->gammas();
    std::vector<double> candela;
    for (size_t i = 0; i < t->planes(); ++i) {
      for (size_t k = 0; k <= old_gammas; ++k) {
        if (k == g) candela.push_back(values[i]);
        if (k < old_gammas) candela.push_back(t->candela[i * old_gammas + k]);
      }
    }
    t->gamma_deg.insert(t->gamma_deg.begin() + static_cast<std::ptrdiff_t>(g), p.gamma_deg);
    t->candela = std::move(candela);
  }
  for (size_t i = 0; i < t->planes(); ++i) {
    if (plane_only == t->planes() || i == plane_only) t->candela[i * t->gammas() + g] = p.candela;
  }
}

}  // namespace relight::baker
