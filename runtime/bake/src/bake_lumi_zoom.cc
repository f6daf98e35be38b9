// The LUMI section's version 4 tail: a luminaire's zoom (bake.h BakeZoom),
// encoder and decoder side by side, field order as in docs/bake-format.md.
// Apart from bake_section_lumi.cc because it is one concept (the zoom optic)
// and versions before 4 have none.
#include "bake_sections.h"

namespace relight::bake_format {

void EncodeLuminaireZoom(const BakeZoom& zoom, ByteWriter* w) {
  w->Put(static_cast<uint32_t>(zoom.profile.size()));
  if (!zoom.present()) return;
  w->Put(zoom.min_deg);
  w->Put(zoom.max_deg);
  w->Put(zoom.default_deg);
  w->Put(zoom.lumens);
  w->Put(zoom.profile_end);
  for (int32_t v : zoom.profile) w->Put(v);
}

Status DecodeLuminaireZoom(ContainerReader* in, const std::string& label, ByteReader* r,
                           BakeZoom* zoom) {
  const uint32_t samples = r->Get<uint32_t>("zoom profile count");
  if (r->failed()) return in->Finish(*r, label);
  if (samples == 0) return Status::Ok();
  if (samples < kMinZoomProfileSamples || samples > kMaxZoomProfileSamples) {
    return in->Corrupt(label, StrFormat("zoom profile has %u samples, outside 0 or [%u, %u]",
                                        samples, kMinZoomProfileSamples, kMaxZoomProfileSamples));
  }
  if (kLumiZoomFixedBytes - 4 + 4 * uint64_t{samples} > r->remaining()) {
    return in->Corrupt(label, "payload too short for the zoom profile");
  }
  zoom->min_deg = r->Get<int32_t>("zoom min");
  zoom->max_deg = r->Get<int32_t>("zoom max");
  zoom->default_deg = r->Get<int32_t>("zoom default");
  zoom->lumens = r->Get<int64_t>("zoom lumens");
  zoom->profile_end = r->Get<int32_t>("zoom profile end");
  zoom->profile.resize(samples);
  for (int32_t& v : zoom->profile) v = r->Get<int32_t>("zoom profile");
  return Status::Ok();
}

}  // namespace relight::bake_format
