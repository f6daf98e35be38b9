// The engine's order of a compressed basis's weights (bake.h
// CompressedWeightOrder::kTiles16). The file keeps each cluster's weights
// component-major (w[j n + i]), so the kernel read r streams n receivers
// apart at once, which the hardware prefetchers follow poorly once 48
// luminaires' weights are far past the cache. Tiled, a cluster is cut into
// runs of 16 receivers (the last may be shorter, m receivers) and a tile
// holds, in turn:
//   for each component pair p < r / 2: receiver q's (w_2p, w_2p+1) at
//     2 m p + 2 q, 2 m p + 2 q + 1 (one 512-bit load is 16 receivers' pair,
//     the operand vpdpwssd takes, no permute);
//   for an odd r, the last component: receiver q's at 2 m (r / 2) + q.
// Tile b of a cluster starts 16 b r values into the cluster's weights, so
// the cluster keeps its place (cluster_start * r) and the array its size.
#pragma once

#include <cstddef>
#include <cstdint>

#include "relight/bake/bake.h"

namespace relight {

inline constexpr uint32_t kWeightTile = 16;

// Where receiver i's (of n in its cluster) component j of r lives in the
// tiled cluster, from the cluster's first weight.
inline size_t TiledWeightOffset(uint32_t n, uint32_t r, uint32_t i, uint32_t j) {
  const uint32_t first = i - i % kWeightTile, q = i % kWeightTile;
  const uint32_t m = n - first < kWeightTile ? n - first : kWeightTile;
  const uint32_t even = r & ~1u;
  const size_t tile = size_t{first} * r;
  return tile + (j < even ? size_t{j / 2} * 2 * m + 2 * q + (j & 1) : size_t{even} * m + q);
}

// One cluster of n receivers and r components: component-major -> tiled
// (the two arrays n x r long, not overlapping).
void TileClusterWeights(const int16_t* component_major, uint32_t n, uint32_t r, int16_t* tiled);

// Every cluster of `cpca` into kTiles16 order, in place (no-op if already
// tiled); an 8-bit basis (weight_bits 8) then moves to `weights8`, a byte a
// weight. Open time only: it allocates one cluster's scratch.
void TileCompressedWeights(BakeCompressedBasis* cpca);

}  // namespace relight
