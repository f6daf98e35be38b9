// ReadBake / ParseBake: trust nothing. The container (bake_container.h)
// checks header and table of contents (magic, version, crc, sizes, layout)
// before any section is read; each section's size is checked against the
// counts before its crc, its crc before it is decompressed, and its
// contents against bake_check.h after (bake_sections.h). Sections are
// parsed into a local Bake, moved to `out` only on success.
#include <string>
#include <utility>
#include <vector>

#include "bake_container.h"
#include "bake_file_io.h"
#include "bake_sections.h"
#include "relight/bake/bake.h"
#include "relight/bake/bake_check.h"
#include "relight/base/sh_index.h"

namespace relight {
namespace {

using namespace bake_format;  // NOLINT: the layout constants read better bare

class Parser {
 public:
  Parser(const uint8_t* data, size_t size, std::string name, const ReadBakeOptions& options = {})
      : in_(data, size, std::move(name)), options_(options) {}
  Parser(const ReadOnlyFile* file, std::string name, const ReadBakeOptions& options)
      : in_(file, std::move(name)), options_(options) {}

  Status Parse(Bake* out) {
    RELIGHT_RETURN_IF_ERROR(in_.Open());
    Bake bake;
    RELIGHT_RETURN_IF_ERROR(DecodeMeta(&in_, &counts_, &bake));
    RELIGHT_RETURN_IF_ERROR(DecodeMesh(&in_, counts_, &bake));
    for (uint32_t g = 0; g < counts_.grids; ++g) RELIGHT_RETURN_IF_ERROR(DecodeGrid(&in_, counts_, g, &bake));
    std::vector<const std::string*> names;
    for (const BakeGrid& grid : bake.grids) names.push_back(&grid.name);
    std::string e = CheckUniqueNames(names, "grid");
    if (!e.empty()) return in_.Corrupt("sections GRID", e);
    for (uint32_t l = 0; l < counts_.luminaires; ++l) {
      RELIGHT_RETURN_IF_ERROR(DecodeLuminaire(&in_, counts_, l, &bake));
    }
    names.clear();
    for (const BakeLuminaire& lum : bake.luminaires) names.push_back(&lum.name);
    e = CheckUniqueNames(names, "luminaire");
    if (!e.empty()) return in_.Corrupt("sections LUMI", e);
    RELIGHT_RETURN_IF_ERROR(CheckSectionCount(bake));
    RELIGHT_RETURN_IF_ERROR(ParseReceivers(&bake));
    if (options_.hierarchy && hierarchy_index_ != 0) {
      RELIGHT_RETURN_IF_ERROR(DecodeHierarchy(&in_, hierarchy_index_, &bake));
    }
    if (options_.hierarchy && grid_links_ && options_.grids) {
      uint32_t points = 0;  // each <= 2^24, at most 64 grids: no wrap
      for (const BakeGrid& grid : bake.grids) points += grid.point_count();
      RELIGHT_RETURN_IF_ERROR(DecodeGridLinks(&in_, hierarchy_index_ + 2, points, &bake));
    }
    if (!options_.grids) {
      bake.grids.clear();
      bake.grids.shrink_to_fit();
      for (BakeLuminaire& lum : bake.luminaires) lum.receivers.resize(1);
    }
    *out = std::move(bake);
    return Status::Ok();
  }

 private:
  std::string ReceiverLabel(const char* tag, uint32_t l, const BakeLuminaire& lum,
                            uint32_t set) const {
    return StrFormat("section %s[lum %u '%s', set %u]", tag, l, lum.name.c_str(), set);
  }

  // The luminaires fix the number of DIRT and BASE sections; HIER and LINK
  // may follow them (version 3 on). Their sizes are checked here, before any
  // of the big sections is decompressed.
  Status CheckSectionCount(const Bake& bake) {
    size_t expected = 2 + size_t{counts_.grids} + counts_.luminaires;
    for (const BakeLuminaire& lum : bake.luminaires) {
      expected += size_t{bake.receiver_set_count()} *
                  (lum.direct_mode == DirectMode::kExactDirect ? 2 : 1);
    }
    const bool hierarchy_allowed = in_.version() >= kFirstVersionWithHierarchy;
    // Version 6 on, a GLNK section may follow LINK.
    grid_links_ = in_.version() >= kFirstVersionWithGridLinks &&
                  in_.section_count() == expected + 3;
    if (hierarchy_allowed && (in_.section_count() == expected + 2 || grid_links_)) {
      hierarchy_index_ = expected;
      if (grid_links_) {
        uint64_t points = 0;
        for (uint32_t p : counts_.grid_points) points += p;
        RELIGHT_RETURN_IF_ERROR(in_.Expect(expected + 2, kTagGridLinks, "section GLNK",
                                           GridLinkBytes(points, 0),
                                           GridLinkBytes(points, kMaxLinks)));
      }
      // Fewer than 2 T nodes (bake_format.h); the node count itself is checked after loading.
      const uint64_t max_nodes = counts_.triangles == 0 ? 0 : 2 * uint64_t{counts_.triangles} - 1;
      RELIGHT_RETURN_IF_ERROR(in_.Expect(expected, kTagHierarchy, "section HIER", HierBytes(1),
                                     HierBytes(max_nodes)));
      return in_.Expect(expected + 1, kTagLinks, "section LINK", LinkBytes(0), LinkBytes(kMaxLinks));
    }
    if (in_.section_count() != expected) {
      std::string also;
      if (hierarchy_allowed) {
        also = in_.version() >= kFirstVersionWithGridLinks
                   ? StrFormat(" (or %zu with HIER and LINK, %zu with GLNK too)", expected + 2,
                               expected + 3)
                   : StrFormat(" (or %zu with HIER and LINK)", expected + 2);
      } else if (in_.section_count() == expected + 2) {
        also = StrFormat(" (HIER and LINK need format version %u, the file has %u)",
                         kFirstVersionWithHierarchy, in_.version());
      }
      return in_.Corrupt("table of contents", StrFormat("%zu sections, the counts need %zu%s",
                                                    in_.section_count(), expected, also.c_str()));
    }
    return Status::Ok();
  }

  // DIRT (exact direct only) then BASE or CPCA, per luminaire per receiver set. All
  // their sizes are checked before the first one is decompressed.
  Status ParseReceivers(Bake* bake) {
    const uint32_t sets = bake->receiver_set_count();
    for (int pass = 0; pass < 2; ++pass) {
      size_t index = 2 + size_t{counts_.grids} + counts_.luminaires;
      for (uint32_t l = 0; l < counts_.luminaires; ++l) {
        BakeLuminaire& lum = bake->luminaires[l];
        const uint64_t terms = static_cast<uint64_t>(ShTermCount(lum.sh_degree));
        lum.receivers.resize(sets);
        for (uint32_t s = 0; s < sets; ++s) {
          const uint32_t count = bake->receiver_count(s);
          // A grid's sections (set 1 on) that the reader does not want: sizes checked, nothing read.
          if (pass == 1 && s >= 1 && !options_.grids) {
            index += lum.direct_mode == DirectMode::kExactDirect ? 2 : 1;
            continue;
          }
          if (lum.direct_mode == DirectMode::kExactDirect) {
            const std::string label = ReceiverLabel("DIRT", l, lum, s);
            if (pass == 0) {
              const uint64_t raw = DirectBytes(count);
              RELIGHT_RETURN_IF_ERROR(in_.Expect(index, kTagDirect, label, raw, raw));
            } else {
              RELIGHT_RETURN_IF_ERROR(
                  DecodeDirect(&in_, index, label, lum.direct_mode, count, &lum.receivers[s]));
            }
            ++index;
          }
          // Version 5 on, a compressed basis (CPCA) may stand for the BASE;
          // version 8 on, one with 8-bit weights (CPC8).
          const bool bytes = in_.version() >= kFirstVersionWith8BitWeights && in_.tag(index) == kTagCompressed8;
          const bool compressed =
              bytes || (in_.version() >= kFirstVersionWithCompressed && in_.tag(index) == kTagCompressed);
          const std::string label = ReceiverLabel(bytes ? "CPC8" : (compressed ? "CPCA" : "BASE"), l, lum, s);
          if (pass == 0 && compressed) {
            RELIGHT_RETURN_IF_ERROR(in_.Expect(index, bytes ? kTagCompressed8 : kTagCompressed, label,
                                               CompressedBytes(terms, count, 1, 0),
                                               MaxCompressedBytes(terms, count)));
          } else if (pass == 0) {
            const uint64_t raw = BasisBytes(terms, count);
            RELIGHT_RETURN_IF_ERROR(in_.Expect(index, kTagBasis, label, raw, raw));
          } else if (compressed) {
            RELIGHT_RETURN_IF_ERROR(DecodeCompressedBasis(&in_, index, label, lum.sh_degree, count,
                                                          bytes ? 8 : 16, &lum.receivers[s]));
          } else {
            RELIGHT_RETURN_IF_ERROR(
                DecodeBasis(&in_, index, label, lum.sh_degree, count, &lum.receivers[s]));
          }
          ++index;
        }
      }
    }
    return Status::Ok();
  }

  ContainerReader in_;
  ReadBakeOptions options_;
  size_t hierarchy_index_ = 0;  // TOC index of HIER (LINK follows); 0: none
  bool grid_links_ = false;     // GLNK follows LINK
  Counts counts_;
};

}  // namespace

Status ParseBake(const uint8_t* data, size_t size, Bake* out) {
  if (data == nullptr && size != 0) return Status(StatusCode::kInvalidArgument, "bake: null data");
  return Parser(data, size, "(in memory)").Parse(out);
}

Status ReadBake(const std::string& path, Bake* out) { return ReadBake(path, ReadBakeOptions{}, out); }

// Section by section from the file: a bake is read into memory once, not
// held twice (file bytes and decoded bake) while it is parsed.
Status ReadBake(const std::string& path, const ReadBakeOptions& options, Bake* out) {
  ReadOnlyFile file;
  RELIGHT_RETURN_IF_ERROR(file.Open(path));
  return Parser(&file, "'" + path + "'", options).Parse(out);
}

}  // namespace relight
