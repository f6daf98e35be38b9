// Section DIRT and BASE: one luminaire on one receiver set: the exact direct term
// (quantised geometry and directions) and the quantised SH basis with its scales.
// Encoder and decoder side by side, field order as in docs/bake-format.md.
#include <string>
#include <utility>
#include <vector>

#include "bake_sections.h"
#include "relight/bake/bake_check.h"
#include "relight/base/sh_index.h"

namespace relight::bake_format {

namespace {

void PutScale(ByteWriter* w, QuantScale s) {
  w->Put(s.mantissa);
  w->Put(s.exponent);
}

}  // namespace

void EncodeDirect(const BakeLightReceivers& rec, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  PutScale(&w, rec.geometry_scale);
  w.PutPlanar(rec.direction, 3);
  w.PutPlanar(rec.geometry, 1);
}

void EncodeBasis(const BakeLightReceivers& rec, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  for (QuantScale s : rec.basis_scale) PutScale(&w, s);
  w.PutPlanar(rec.basis, 3);
}

Status DecodeDirect(ContainerReader* in, size_t index, const std::string& label, DirectMode mode, uint32_t count,
                   BakeLightReceivers* rec) {
  ByteReader r(nullptr, 0);
  RELIGHT_RETURN_IF_ERROR(in->Load(index, label, &r));
  rec->geometry_scale.mantissa = r.Get<int32_t>("geometry_scale");
  rec->geometry_scale.exponent = r.Get<int32_t>("geometry_scale");
  r.GetPlanar(&rec->direction, 3 * size_t{count}, 3, "direction");
  r.GetPlanar(&rec->geometry, size_t{count}, 1, "geometry");
  RELIGHT_RETURN_IF_ERROR(in->Finish(r, label));
  const std::string e = CheckDirect(*rec, mode, count);
  if (!e.empty()) return in->Corrupt(label, e);
  return Status::Ok();
}

Status DecodeBasis(ContainerReader* in, size_t index, const std::string& label, int degree, uint32_t count,
                  BakeLightReceivers* rec) {
  ByteReader r(nullptr, 0);
  RELIGHT_RETURN_IF_ERROR(in->Load(index, label, &r));
  const auto terms = static_cast<size_t>(ShTermCount(degree));
  rec->basis_scale.resize(3 * terms);
  for (QuantScale& s : rec->basis_scale) {
    s.mantissa = r.Get<int32_t>("basis_scale");
    s.exponent = r.Get<int32_t>("basis_scale");
  }
  r.GetPlanar(&rec->basis, 3 * terms * count, 3, "basis");
  RELIGHT_RETURN_IF_ERROR(in->Finish(r, label));
  const std::string e = CheckBasis(*rec, degree, count);
  if (!e.empty()) return in->Corrupt(label, e);
  return Status::Ok();
}

}  // namespace relight::bake_format
