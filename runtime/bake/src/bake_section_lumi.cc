// Section LUMI: one luminaire (name, pose, modes, defaults, LID; version 2 on: orientation,
// console ranges, the (C, gamma) table and its SH coefficients; version 4 on:
// the zoom, bake_lumi_zoom.cc).
// Encoder and decoder side by side, field order as in docs/bake-format.md.
#include <string>
#include <utility>
#include <vector>

#include "bake_sections.h"
#include "relight/bake/bake_check.h"
#include "relight/base/sh_index.h"

using ull = unsigned long long;

namespace relight::bake_format {

namespace {

// Version 2: orientation, console ranges, the (C, gamma) table and its SH
// coefficients. Counts are checked before anything is allocated.
Status DecodeLuminaireTail(ContainerReader* in, const std::string& label, ByteReader* r,
                           BakeLuminaire* lum) {
  lum->yaw = r->Get<int32_t>("yaw");
  lum->roll = r->Get<int32_t>("roll");
  lum->pan_range = r->Get<int32_t>("pan range");
  lum->tilt_range = r->Get<int32_t>("tilt range");
  const uint32_t planes = r->Get<uint32_t>("LID plane count");
  const uint32_t gammas = r->Get<uint32_t>("LID gamma count");
  if (r->failed()) return in->Finish(*r, label);
  if ((planes == 0) != (gammas == 0) || planes > kMaxLidPlanes || gammas > kMaxLidGammas ||
      uint64_t{planes} * gammas > kMaxLidTableValues) {
    return in->Corrupt(label, StrFormat("LID table of %u planes x %u gammas is outside the limits "
                                    "(0 x 0, or [%u, %u] x [%u, %u] and at most %llu values)",
                                    planes, gammas, kMinLidPlanes, kMaxLidPlanes, kMinLidGammas,
                                    kMaxLidGammas, static_cast<ull>(kMaxLidTableValues)));
  }
  const uint64_t need = LumiTailBytes(planes, gammas, 0) - kLumiTailFixedBytes;
  if (need > r->remaining()) return in->Corrupt(label, "payload too short for the LID table");
  lum->lid.c_deg.resize(planes);
  lum->lid.gamma_deg.resize(gammas);
  lum->lid.table.resize(size_t{planes} * gammas);
  for (int32_t& v : lum->lid.c_deg) v = r->Get<int32_t>("LID C angle");
  for (int32_t& v : lum->lid.gamma_deg) v = r->Get<int32_t>("LID gamma angle");
  for (int64_t& v : lum->lid.table) v = r->Get<int64_t>("LID table");
  const uint32_t terms = r->Get<uint32_t>("LID SH coefficient count");
  if (r->failed()) return in->Finish(*r, label);
  if (terms > static_cast<uint32_t>(ShTermCount(kMaxShDegree)) || uint64_t{terms} * 8 > r->remaining()) {
    return in->Corrupt(label, StrFormat("LID has %u SH coefficients (at most %d, and the payload "
                                    "must hold them)",
                                    terms, ShTermCount(kMaxShDegree)));
  }
  lum->lid.sh.resize(terms);
  for (int64_t& v : lum->lid.sh) v = r->Get<int64_t>("LID SH coefficient");
  return Status::Ok();
}

}  // namespace

void EncodeLuminaire(const BakeLuminaire& lum, uint32_t version, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  w.PutString(lum.name);
  for (int32_t v : lum.position) w.Put(v);
  w.Put(static_cast<uint8_t>(lum.mounting));
  w.Put(static_cast<uint8_t>(lum.direct_mode));
  w.Put(lum.sh_degree);
  w.Put(lum.use_sigma);
  w.Put(lum.default_pan);
  w.Put(lum.default_tilt);
  w.Put(lum.default_dimmer);
  for (int16_t v : lum.default_rgb) w.Put(v);
  w.Put(static_cast<uint32_t>(lum.lid.candela.size()));
  for (int64_t cd : lum.lid.candela) w.Put(cd);
  // Version 2 tail.
  w.Put(lum.yaw);
  w.Put(lum.roll);
  w.Put(lum.pan_range);
  w.Put(lum.tilt_range);
  w.Put(static_cast<uint32_t>(lum.lid.c_deg.size()));
  w.Put(static_cast<uint32_t>(lum.lid.gamma_deg.size()));
  for (int32_t v : lum.lid.c_deg) w.Put(v);
  for (int32_t v : lum.lid.gamma_deg) w.Put(v);
  for (int64_t v : lum.lid.table) w.Put(v);
  w.Put(static_cast<uint32_t>(lum.lid.sh.size()));
  for (int64_t v : lum.lid.sh) w.Put(v);
  if (version >= kFirstVersionWithZoom) EncodeLuminaireZoom(lum.zoom, &w);
}

Status DecodeLuminaire(ContainerReader* in, const Counts& counts, uint32_t l, Bake* bake) {
  const std::string label = StrFormat("section LUMI[%u]", l);
  const size_t index = 2 + counts.grids + l;
  const bool tail = in->version() >= 2;
  const bool zoom = in->version() >= kFirstVersionWithZoom;
  RELIGHT_RETURN_IF_ERROR(in->Expect(
      index, kTagLumi, label,
      LumiBytes(1, kMinLidSamples) + (tail ? kLumiTailFixedBytes : 0) + (zoom ? 4 : 0),
      LumiBytes(kMaxNameBytes, kMaxLidSamples) + (tail ? kMaxLumiTailBytes : 0) +
          (zoom ? kMaxLumiZoomBytes : 0)));
  ByteReader r(nullptr, 0);
  RELIGHT_RETURN_IF_ERROR(in->Load(index, label, &r));
  BakeLuminaire lum;
  r.GetString(&lum.name, kMaxNameBytes, "name");
  for (int32_t& v : lum.position) v = r.Get<int32_t>("position");
  lum.mounting = static_cast<Mounting>(r.Get<uint8_t>("mounting"));
  lum.direct_mode = static_cast<DirectMode>(r.Get<uint8_t>("direct mode"));
  lum.sh_degree = r.Get<uint8_t>("SH degree");
  lum.use_sigma = r.Get<uint8_t>("use_sigma");
  lum.default_pan = r.Get<int32_t>("default pan");
  lum.default_tilt = r.Get<int32_t>("default tilt");
  lum.default_dimmer = r.Get<int16_t>("default dimmer");
  for (int16_t& v : lum.default_rgb) v = r.Get<int16_t>("default colour");
  const uint32_t samples = r.Get<uint32_t>("LID sample count");
  if (r.failed()) return in->Finish(r, label);
  if (samples < kMinLidSamples || samples > kMaxLidSamples) {
    return in->Corrupt(label, StrFormat("LID has %u samples, outside [%u, %u]", samples,
                                    kMinLidSamples, kMaxLidSamples));
  }
  if (samples > r.remaining() / 8) return in->Corrupt(label, "payload too short for the LID samples");
  lum.lid.candela.resize(samples);
  for (int64_t& cd : lum.lid.candela) cd = r.Get<int64_t>("LID");
  if (tail) RELIGHT_RETURN_IF_ERROR(DecodeLuminaireTail(in, label, &r, &lum));
  if (zoom) RELIGHT_RETURN_IF_ERROR(DecodeLuminaireZoom(in, label, &r, &lum.zoom));
  RELIGHT_RETURN_IF_ERROR(in->Finish(r, label));
  const std::string e = CheckLuminaire(lum);
  if (!e.empty()) return in->Corrupt(label, e);
  if (lum.sh_degree > kMaxShDegreeBeforeVersion7 && in->version() < kFirstVersionWithHighDegree) {
    return in->Corrupt(label, StrFormat("SH degree %u needs format version %u, the file has %u", lum.sh_degree,
                                        kFirstVersionWithHighDegree, in->version()));
  }
  bake->luminaires.push_back(std::move(lum));
  return Status::Ok();
}

}  // namespace relight::bake_format
