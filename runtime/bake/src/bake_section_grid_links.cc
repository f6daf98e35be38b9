// Section GLNK (format version 6): links from the hierarchy's nodes to the
// calculation grids' points, for run-time emitters on the grids. A point
// count and a link count, then planar arrays (docs/bake-format.md).
#include <string>
#include <utility>

#include "bake_sections.h"
#include "relight/bake/bake_check.h"

namespace relight::bake_format {

void EncodeGridLinks(const BakeHierarchy& h, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  w.Put(static_cast<uint32_t>(h.grid_link_offsets.size() - 1));
  w.Put(static_cast<uint32_t>(h.grid_link_node.size()));
  w.PutPlanar(h.grid_link_offsets, 1);
  w.PutPlanar(h.grid_link_node, 1);
  w.PutPlanar(h.grid_link_f, 1);
}

Status DecodeGridLinks(ContainerReader* in, size_t index, uint32_t grid_points, Bake* bake) {
  const std::string label = "section GLNK";
  ByteReader r(nullptr, 0);
  RELIGHT_RETURN_IF_ERROR(in->Load(index, label, &r));
  const uint32_t points = r.Get<uint32_t>("point count");
  const uint32_t links = r.Get<uint32_t>("link count");
  if (r.failed()) return in->Corrupt(label, r.error());
  if (points != grid_points) {
    return in->Corrupt(label, StrFormat("point count %u, the grids have %u", points, grid_points));
  }
  if (links > kMaxLinks) {
    return in->Corrupt(label, StrFormat("%u links exceed the limit %u", links, kMaxLinks));
  }
  // The raw size must be exactly what the counts say, before anything is allocated.
  if (in->raw_size(index) != GridLinkBytes(points, links)) {
    return in->Corrupt(label, StrFormat("raw size %llu, %u points and %u links need %llu",
                                        static_cast<unsigned long long>(in->raw_size(index)), points,
                                        links,
                                        static_cast<unsigned long long>(GridLinkBytes(points, links))));
  }
  BakeHierarchy& h = *bake->hierarchy;
  r.GetPlanar(&h.grid_link_offsets, size_t{points} + 1, 1, "grid link offsets");
  r.GetPlanar(&h.grid_link_node, links, 1, "grid link node");
  r.GetPlanar(&h.grid_link_f, links, 1, "grid link f");
  RELIGHT_RETURN_IF_ERROR(in->Finish(r, label));
  const std::string e = CheckGridLinks(h, grid_points);
  if (!e.empty()) return in->Corrupt(label, e);
  return Status::Ok();
}

}  // namespace relight::bake_format
