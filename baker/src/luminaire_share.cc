// The split of a bake's right-hand sides over ranks (distributed.h).
#include <algorithm>
#include <cstdint>
#include <numeric>

#include "relight/base/sh_index.h"
#include "relight/baker/distributed.h"

namespace relight::baker {

std::vector<int> ShareLuminaires(const Scene& scene, int ranks) {
  const size_t n = scene.luminaires.size();
  std::vector<int> owner(n, 0);
  if (ranks <= 1) return owner;
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  const auto terms = [&](size_t l) { return ShTermCount(scene.luminaires[l].sh_degree); };
  // A solve's time grows with its columns: largest first balances the ranks.
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return terms(a) > terms(b); });
  std::vector<int64_t> load(static_cast<size_t>(ranks), 0);
  for (size_t l : order) {
    const auto least = std::min_element(load.begin(), load.end()) - load.begin();
    owner[l] = static_cast<int>(least);
    load[static_cast<size_t>(least)] += terms(l);
  }
  return owner;
}

}  // namespace relight::baker
