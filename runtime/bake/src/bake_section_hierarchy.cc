// Sections HIER and LINK: the hierarchical solver's nodes and links. Both
// are a count then planar arrays, so one visitor per section lists its
// arrays (field order as in docs/bake-format.md) and serves the encoder and
// the decoder alike.
#include <string>
#include <utility>
#include <vector>

#include "bake_sections.h"
#include "relight/bake/bake_check.h"

namespace relight::bake_format {
namespace {

// f(array, values per item, name) for each HIER array, in file order.
template <typename H, typename F>
void ForEachNodeArray(H& h, F&& f) {
  f(h.node_surface, 1, "node surface");
  f(h.node_parent, 1, "node parent");
  f(h.node_first_child, 1, "node first child");
  f(h.node_child_count, 1, "node child count");
  f(h.node_corner_count, 1, "node corner count");
  f(h.node_corners, kBakeMaxNodeCorners, "node corners");
  f(h.node_area, 1, "node area");
  f(h.node_leaf_triangle, 1, "node leaf triangle");
}

// The same for LINK.
template <typename H, typename F>
void ForEachLinkArray(H& h, F&& f) {
  f(h.link_p, 1, "link p");
  f(h.link_q, 1, "link q");
  f(h.link_f_pq, 1, "link f_pq");
  f(h.link_f_qp, 1, "link f_qp");
  f(h.link_g_pq, 2, "link g_pq");
  f(h.link_g_qp, 2, "link g_qp");
}

template <typename ForEach>
void EncodeCounted(const BakeHierarchy& h, uint32_t count, ForEach for_each,
                   std::vector<uint8_t>* out) {
  ByteWriter w(out);
  w.Put(count);
  for_each(h, [&](const auto& values, size_t stride, const char*) { w.PutPlanar(values, stride); });
}

// Loads section `index` (count, then the arrays) into h and runs its check.
template <typename ForEach>
Status DecodeCounted(ContainerReader* in, size_t index, const std::string& label,
                     uint64_t (*bytes)(uint64_t), const char* items, ForEach for_each,
                     BakeHierarchy* h) {
  ByteReader r(nullptr, 0);
  uint32_t count = 0;
  RELIGHT_RETURN_IF_ERROR(in->LoadCounted(index, label, bytes, items, &r, &count));
  for_each(*h, [&](auto& values, size_t stride, const char* what) {
    r.GetPlanar(&values, size_t{count} * stride, stride, what);
  });
  return in->Finish(r, label);
}

}  // namespace

void EncodeHierarchyNodes(const BakeHierarchy& h, std::vector<uint8_t>* out) {
  EncodeCounted(h, h.node_count(), [](auto& hh, auto f) { ForEachNodeArray(hh, f); }, out);
}

void EncodeHierarchyLinks(const BakeHierarchy& h, std::vector<uint8_t>* out) {
  EncodeCounted(h, h.link_count(), [](auto& hh, auto f) { ForEachLinkArray(hh, f); }, out);
}

Status DecodeHierarchy(ContainerReader* in, size_t index, Bake* bake) {
  BakeHierarchy h;
  RELIGHT_RETURN_IF_ERROR(DecodeCounted(in, index, "section HIER", HierBytes, "nodes",
                                        [](auto& hh, auto f) { ForEachNodeArray(hh, f); }, &h));
  std::string e = CheckHierarchyNodes(h, bake->mesh);
  if (!e.empty()) return in->Corrupt("section HIER", e);
  RELIGHT_RETURN_IF_ERROR(DecodeCounted(in, index + 1, "section LINK", LinkBytes, "links",
                                        [](auto& hh, auto f) { ForEachLinkArray(hh, f); }, &h));
  e = CheckHierarchyLinks(h);
  if (!e.empty()) return in->Corrupt("section LINK", e);
  bake->hierarchy = std::move(h);
  return Status::Ok();
}

}  // namespace relight::bake_format
