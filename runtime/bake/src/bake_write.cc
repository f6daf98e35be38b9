// WriteBake: validate (ValidateBake), encode every section (bake_sections.h),
// store them through the container (bake_container.h: zstd, crc, TOC), and
// write atomically (bake_file_io.h): a temporary file beside the target,
// fsync, rename over the target. Any failure removes the temporary file and
// leaves the target as it was.
#include <string>
#include <vector>

#include "bake_container.h"
#include "bake_file_io.h"
#include "bake_sections.h"
#include "relight/bake/bake.h"

namespace relight {
namespace {

using namespace bake_format;  // NOLINT: the layout constants read better bare

uint32_t SectionCount(const Bake& bake) {
  uint32_t n = 2 + static_cast<uint32_t>(bake.grids.size() + bake.luminaires.size());
  for (const BakeLuminaire& lum : bake.luminaires) {
    const uint32_t per_set = lum.direct_mode == DirectMode::kExactDirect ? 2 : 1;
    n += per_set * bake.receiver_set_count();
  }
  if (!bake.hierarchy) return n;
  return n + (bake.hierarchy->has_grid_links() ? 3 : 2);
}

// The lowest version that holds the bake, so older readers read what they can.
uint32_t FileVersion(const Bake& bake) {
  for (const BakeLuminaire& lum : bake.luminaires) {
    for (const BakeLightReceivers& rec : lum.receivers) {
      if (rec.compressed.present() && rec.compressed.weight_bits == 8) return kFirstVersionWith8BitWeights;
    }
  }
  for (const BakeLuminaire& lum : bake.luminaires) {
    if (lum.sh_degree > kMaxShDegreeBeforeVersion7) return kFirstVersionWithHighDegree;
  }
  if (bake.hierarchy && bake.hierarchy->has_grid_links()) return kFirstVersionWithGridLinks;
  for (const BakeLuminaire& lum : bake.luminaires) {
    for (const BakeLightReceivers& rec : lum.receivers) {
      if (rec.compressed.present()) return kFirstVersionWithCompressed;
    }
  }
  for (const BakeLuminaire& lum : bake.luminaires) {
    if (lum.zoom.present()) return kFirstVersionWithZoom;
  }
  return bake.hierarchy ? kFirstVersionWithHierarchy : kVersionWithoutHierarchy;
}

// Writes every section in TOC order behind the space for the header and TOC,
// then them. Returns false with errno set on an I/O failure.
bool WriteSections(const Bake& bake, int fd, std::vector<BakeSectionSize>* sizes) {
  const uint32_t sections = SectionCount(bake);
  const uint32_t version = FileVersion(bake);
  SectionSink sink(fd, kHeaderBytes + kTocEntryBytes * sections);
  std::vector<uint8_t> raw;
  auto add = [&](uint32_t tag, auto encode) {
    raw.clear();
    encode(&raw);
    return sink.Add(tag, raw);
  };
  bool ok = add(kTagMeta, [&](std::vector<uint8_t>* o) { EncodeMeta(bake, o); }) &&
            add(kTagMesh, [&](std::vector<uint8_t>* o) { EncodeMesh(bake.mesh, o); });
  for (const BakeGrid& grid : bake.grids) {
    ok = ok && add(kTagGrid, [&](std::vector<uint8_t>* o) { EncodeGrid(grid, o); });
  }
  for (const BakeLuminaire& lum : bake.luminaires) {
    ok = ok && add(kTagLumi, [&](std::vector<uint8_t>* o) { EncodeLuminaire(lum, version, o); });
  }
  for (const BakeLuminaire& lum : bake.luminaires) {
    for (const BakeLightReceivers& rec : lum.receivers) {
      if (lum.direct_mode == DirectMode::kExactDirect) {
        ok = ok && add(kTagDirect, [&](std::vector<uint8_t>* o) { EncodeDirect(rec, o); });
      }
      if (rec.compressed.present()) {
        ok = ok && add(rec.compressed.weight_bits == 8 ? kTagCompressed8 : kTagCompressed,
                       [&](std::vector<uint8_t>* o) { EncodeCompressedBasis(rec.compressed, o); });
      } else {
        ok = ok && add(kTagBasis, [&](std::vector<uint8_t>* o) { EncodeBasis(rec, o); });
      }
    }
  }
  if (bake.hierarchy) {
    const BakeHierarchy& h = *bake.hierarchy;
    ok = ok && add(kTagHierarchy, [&](std::vector<uint8_t>* o) { EncodeHierarchyNodes(h, o); }) &&
         add(kTagLinks, [&](std::vector<uint8_t>* o) { EncodeHierarchyLinks(h, o); });
    if (h.has_grid_links()) {
      ok = ok && add(kTagGridLinks, [&](std::vector<uint8_t>* o) { EncodeGridLinks(h, o); });
    }
  }
  if (!ok) return false;
  RELIGHT_CHECK(sink.toc().size() == sections);
  const std::vector<uint8_t> header = EncodeHeader(version, sink.toc(), sink.end());
  if (!WriteAt(fd, header.data(), header.size(), 0)) return false;
  if (sizes) {
    sizes->clear();
    for (const TocEntry& e : sink.toc()) {
      BakeSectionSize size;
      for (int i = 0; i < 4; ++i) size.tag[i] = static_cast<char>(e.tag >> (8 * i));
      size.raw_bytes = e.raw;
      size.stored_bytes = e.stored;
      sizes->push_back(size);
    }
  }
  return true;
}

}  // namespace

Status WriteBake(const Bake& bake, const std::string& path, std::vector<BakeSectionSize>* sizes) {
  if (path.empty()) return Status(StatusCode::kInvalidArgument, "bake: empty path");
  RELIGHT_RETURN_IF_ERROR(ValidateBake(bake));
  return WriteFileAtomically(path, [&](int fd) { return WriteSections(bake, fd, sizes); });
}

}  // namespace relight
