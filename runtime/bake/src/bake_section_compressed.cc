// Section CPCA (version 5 on): one luminaire's basis on one receiver set in
// clustered-PCA form (bake.h BakeCompressedBasis), standing where its BASE
// would. Encoder and decoder side by side, field order as in docs/bake-format.md.
// The counts are read and checked against the section's raw size before
// anything is allocated from them.
#include <string>
#include <vector>

#include "bake_sections.h"
#include "relight/bake/bake_check.h"
#include "relight/base/sh_index.h"
#include "relight/base/status.h"

using ull = unsigned long long;

namespace relight::bake_format {

void EncodeCompressedBasis(const BakeCompressedBasis& cpca, std::vector<uint8_t>* out) {
  // The engine's tiled copy is a run-time form only (bake.h).
  RELIGHT_CHECK(cpca.weight_order == CompressedWeightOrder::kComponentMajor);
  ByteWriter w(out);
  w.Put(cpca.cluster_count());
  w.Put(cpca.components);
  for (uint32_t s : cpca.cluster_start) w.Put(s);
  for (QuantScale s : cpca.vector_scale) {
    w.Put(s.mantissa);
    w.Put(s.exponent);
  }
  w.PutPlanar(cpca.vectors, 3);
  if (cpca.weight_bits == 8) {
    // CPC8: a byte a weight (the writer's caller checked they fit).
    const std::vector<int8_t> bytes(cpca.weights.begin(), cpca.weights.end());
    w.PutPlanar(bytes, 1);
  } else {
    w.PutPlanar(cpca.weights, 1);
  }
}

Status DecodeCompressedBasis(ContainerReader* in, size_t index, const std::string& label, int degree,
                             uint32_t count, uint8_t weight_bits, BakeLightReceivers* rec) {
  ByteReader r(nullptr, 0);
  RELIGHT_RETURN_IF_ERROR(in->Load(index, label, &r));
  BakeCompressedBasis& cpca = rec->compressed;
  cpca.weight_bits = weight_bits;
  const uint64_t weight_bytes = weight_bits == 8 ? 1 : 2;
  const uint32_t clusters = r.Get<uint32_t>("cluster count");
  cpca.components = r.Get<uint32_t>("component count");
  if (r.failed()) return in->Finish(r, label);
  const uint64_t terms = static_cast<uint64_t>(ShTermCount(degree));
  if (clusters == 0 || clusters > count || cpca.components > kMaxCompressedComponents ||
      uint64_t{clusters} * (cpca.components + 1) > MaxCompressedVectors(count)) {
    return in->Corrupt(label, StrFormat("%u clusters x %u components is outside the limits for %u "
                                        "receivers (1 .. receivers clusters, at most %u components, "
                                        "clusters x (components + 1) <= receivers + %u)",
                                        clusters, cpca.components, count, kMaxCompressedComponents,
                                        kMaxCompressedComponents + 1));
  }
  const uint64_t need = CompressedBytes(terms, count, clusters, cpca.components, weight_bytes);
  if (in->raw_size(index) != need) {
    return in->Corrupt(label, StrFormat("raw size %llu, the counts need %llu",
                                        static_cast<ull>(in->raw_size(index)), static_cast<ull>(need)));
  }
  cpca.cluster_start.resize(size_t{clusters} + 1);
  for (uint32_t& s : cpca.cluster_start) s = r.Get<uint32_t>("cluster start");
  cpca.vector_scale.resize(3 * terms);
  for (QuantScale& s : cpca.vector_scale) {
    s.mantissa = r.Get<int32_t>("vector_scale");
    s.exponent = r.Get<int32_t>("vector_scale");
  }
  r.GetPlanar(&cpca.vectors, 3 * terms * clusters * (cpca.components + 1), 3, "vectors");
  if (weight_bits == 8) {
    std::vector<int8_t> bytes;
    r.GetPlanar(&bytes, size_t{count} * cpca.components, 1, "weights");
    cpca.weights.assign(bytes.begin(), bytes.end());
  } else {
    r.GetPlanar(&cpca.weights, size_t{count} * cpca.components, 1, "weights");
  }
  RELIGHT_RETURN_IF_ERROR(in->Finish(r, label));
  const std::string e = CheckCompressedBasis(cpca, degree, count);
  if (!e.empty()) return in->Corrupt(label, e);
  return Status::Ok();
}

}  // namespace relight::bake_format
