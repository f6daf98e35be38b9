// Weights into the engine's tiled order: see compressed_tiles.h.
#include "compressed_tiles.h"

#include <vector>

namespace relight {

void TileClusterWeights(const int16_t* component_major, uint32_t n, uint32_t r, int16_t* tiled) {
  for (uint32_t j = 0; j < r; ++j) {
    for (uint32_t i = 0; i < n; ++i) {
      tiled[TiledWeightOffset(n, r, i, j)] = component_major[size_t{j} * n + i];
    }
  }
}

void TileCompressedWeights(BakeCompressedBasis* cpca) {
  if (cpca->weight_order == CompressedWeightOrder::kTiles16 || !cpca->present()) return;
  const uint32_t r = cpca->components;
  std::vector<int16_t> cluster;
  for (uint32_t c = 0; c < cpca->cluster_count(); ++c) {
    const uint32_t start = cpca->cluster_start[c], n = cpca->cluster_start[c + 1] - start;
    int16_t* w = cpca->weights.data() + size_t{start} * r;
    cluster.assign(w, w + size_t{n} * r);
    TileClusterWeights(cluster.data(), n, r, w);
  }
  cpca->weight_order = CompressedWeightOrder::kTiles16;
  if (cpca->weight_bits == 8) {
    // A byte a weight (the bake checked every one is in [-127, 127]); the
    // int16 copy is freed, so an 8-bit basis holds half the bytes.
    cpca->weights8.assign(cpca->weights.begin(), cpca->weights.end());
    std::vector<int16_t>().swap(cpca->weights);
  }
}

}  // namespace relight
