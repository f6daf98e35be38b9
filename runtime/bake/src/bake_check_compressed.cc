// The consistency rules of a compressed basis (bake.h BakeCompressedBasis),
// shared by the writer and the reader like the rest of bake_check.h. Every
// count and index the engine uses is checked here, so the engine can trust
// them (clusters, starts, weight range).
#include <cstdint>

#include "bake_format.h"
#include "relight/bake/bake_check.h"
#include "relight/bake/bake_limits.h"
#include "relight/base/sh_index.h"
#include "relight/base/status.h"

using ull = unsigned long long;

namespace relight::bake_format {
namespace {

std::string CheckStarts(const BakeCompressedBasis& cpca, uint32_t receivers) {
  const uint64_t clusters = cpca.cluster_count();
  if (clusters == 0 || clusters > receivers) {
    return StrFormat("%llu clusters for %u receivers (need 1 .. receivers)", static_cast<ull>(clusters),
                     receivers);
  }
  if (cpca.cluster_start.front() != 0 || cpca.cluster_start.back() != receivers) {
    return StrFormat("cluster starts run from %u to %u, expected 0 to the receiver count %u",
                     cpca.cluster_start.front(), cpca.cluster_start.back(), receivers);
  }
  for (uint64_t c = 0; c < clusters; ++c) {
    if (cpca.cluster_start[c + 1] <= cpca.cluster_start[c]) {
      return StrFormat("cluster %llu is empty or reversed (start %u, next start %u)",
                       static_cast<ull>(c), cpca.cluster_start[c], cpca.cluster_start[c + 1]);
    }
  }
  return "";
}

}  // namespace

std::string CheckCompressedBasis(const BakeCompressedBasis& cpca, int sh_degree, uint32_t receivers) {
  if (sh_degree < 0 || sh_degree > kMaxShDegree) {
    return StrFormat("SH degree %d exceeds the maximum %d", sh_degree, kMaxShDegree);
  }
  if (cpca.components > kMaxCompressedComponents) {
    return StrFormat("%u components, at most %u", cpca.components, kMaxCompressedComponents);
  }
  std::string e = CheckStarts(cpca, receivers);
  if (!e.empty()) return e;
  const uint64_t terms = static_cast<uint64_t>(ShTermCount(sh_degree));
  const uint64_t vectors = uint64_t{cpca.cluster_count()} * (cpca.components + 1);
  if (vectors > MaxCompressedVectors(receivers)) {
    return StrFormat("%llu clusters x (components + 1) = %llu vectors, more than receivers + %u",
                     static_cast<ull>(cpca.cluster_count()), static_cast<ull>(vectors),
                     kMaxCompressedComponents + 1);
  }
  if (cpca.vector_scale.size() != 3 * terms) {
    return CountMismatch("vector_scale", cpca.vector_scale.size(), "3 x terms", 3 * terms);
  }
  if (cpca.vectors.size() != 3 * terms * vectors) {
    return CountMismatch("vectors", cpca.vectors.size(), "3 x terms x clusters x (components + 1)",
                         3 * terms * vectors);
  }
  if (cpca.weights.size() != uint64_t{receivers} * cpca.components) {
    return CountMismatch("weights", cpca.weights.size(), "receivers x components",
                         uint64_t{receivers} * cpca.components);
  }
  for (uint64_t i = 0; i < 3 * terms; ++i) {
    e = CheckScale(cpca.vector_scale[i]);
    if (!e.empty()) {
      return StrFormat("vector_scale[term %llu][channel %llu]: %s", static_cast<ull>(i / 3),
                       static_cast<ull>(i % 3), e.c_str());
    }
    if (cpca.vector_scale[i].mantissa != 0) continue;
    // A zero scale means an all-zero row (fixed.h QuantScale).
    for (uint64_t v = 0; v < vectors; ++v) {
      if (cpca.vectors[((i / 3) * vectors + v) * 3 + i % 3] != 0) {
        return StrFormat("term %llu channel %llu: zero scale but vector %llu is not 0",
                         static_cast<ull>(i / 3), static_cast<ull>(i % 3), static_cast<ull>(v));
      }
    }
  }
  if (cpca.weight_bits != 8 && cpca.weight_bits != 16) {
    return StrFormat("weights of %d bits (8 or 16)", cpca.weight_bits);
  }
  const int32_t one = CompressedWeightOne(cpca.weight_bits);
  for (size_t i = 0; i < cpca.weights.size(); ++i) {
    const int16_t w = cpca.weights[i];
    if (w < -one || w > one) {
      return StrFormat("weight %zu is %d, outside [-%d, %d] (%d-bit weights)", i, w, one, one,
                       cpca.weight_bits);
    }
  }
  return "";
}

}  // namespace relight::bake_format
