// ReadBake / ParseBake: trust nothing. The header and table of contents are
// checked (magic, version, crc, sizes, layout) before any section is read;
// each section's size is checked against the counts before its crc, its crc
// before it is decompressed, and its contents against bake_check.h after.
// Sections are parsed into a local Bake, moved to `out` only on success.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <cerrno>
#include <cstring>
#include <memory>

#include "bake_bytes.h"
#include "relight/bake/bake_check.h"
#include "bake_format.h"
#include "relight/bake/bake.h"
#include "relight/base/sh_index.h"

namespace relight {
namespace {

using namespace bake_format;  // NOLINT: the layout constants read better bare
using ull = unsigned long long;

// The counts META declares; every later section is sized from them.
struct Counts {
  uint32_t vertices = 0, triangles = 0, surfaces = 0, grids = 0, luminaires = 0;
  std::vector<uint32_t> grid_points;
};

std::string TagName(uint32_t tag) {
  char s[5] = {};
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>(tag >> (8 * i));
    if (c < 'A' || c > 'Z') return StrFormat("0x%08X", tag);
    s[i] = c;
  }
  return s;
}

template <typename T>
bool FitsSizeT(T v) {
  return static_cast<uint64_t>(static_cast<size_t>(v)) == static_cast<uint64_t>(v);
}

struct DctxDeleter {
  void operator()(ZSTD_DCtx* d) const { ZSTD_freeDCtx(d); }
};

class Parser {
 public:
  Parser(const uint8_t* data, size_t size, std::string name)
      : data_(data), size_(size), name_(std::move(name)) {}

  Status Parse(Bake* out) {
    RELIGHT_RETURN_IF_ERROR(ReadHeader());
    RELIGHT_RETURN_IF_ERROR(ReadToc());
    Bake bake;
    RELIGHT_RETURN_IF_ERROR(ParseMeta(&bake));
    RELIGHT_RETURN_IF_ERROR(ParseMesh(&bake));
    for (uint32_t g = 0; g < counts_.grids; ++g) RELIGHT_RETURN_IF_ERROR(ParseGrid(g, &bake));
    std::vector<const std::string*> names;
    for (const BakeGrid& grid : bake.grids) names.push_back(&grid.name);
    std::string e = CheckUniqueNames(names, "grid");
    if (!e.empty()) return Corrupt("sections GRID", e);
    for (uint32_t l = 0; l < counts_.luminaires; ++l) {
      RELIGHT_RETURN_IF_ERROR(ParseLuminaire(l, &bake));
    }
    names.clear();
    for (const BakeLuminaire& lum : bake.luminaires) names.push_back(&lum.name);
    e = CheckUniqueNames(names, "luminaire");
    if (!e.empty()) return Corrupt("sections LUMI", e);
    RELIGHT_RETURN_IF_ERROR(CheckSectionCount(bake));
    RELIGHT_RETURN_IF_ERROR(ParseReceivers(&bake));
    if (hierarchy_index_ != 0) RELIGHT_RETURN_IF_ERROR(ParseHierarchy(&bake));
    *out = std::move(bake);
    return Status::Ok();
  }

 private:
  Status Corrupt(const std::string& where, const std::string& what) const {
    return Status(StatusCode::kCorrupt, "bake " + name_ + ": " + where + ": " + what);
  }

  Status ReadHeader() {
    const char* where = "header";
    if (size_ == 0) return Corrupt(where, "empty file");
    const size_t have = size_ < sizeof(kMagic) ? size_ : sizeof(kMagic);
    if (std::memcmp(data_, kMagic, have) != 0) {
      return Corrupt(where, "bad magic, not a relight bake");
    }
    if (size_ < kHeaderBytes) {
      return Corrupt(
          where, StrFormat("truncated: %zu bytes, the header alone is %zu", size_, kHeaderBytes));
    }
    const uint32_t version = LoadLe<uint32_t>(data_ + kVersionOffset);
    if (version > kVersion) {
      // Only magic and version are promised to stay put across versions.
      return Status(StatusCode::kUnsupported,
                    StrFormat("bake %s: format version %u is newer than this build reads (%u)",
                              name_.c_str(), version, kVersion));
    }
    if (version == 0) return Corrupt(where, "format version 0");
    version_ = version;
    const uint32_t sections = LoadLe<uint32_t>(data_ + kSectionCountOffset);
    if (sections < 2 || sections > kMaxSections) {
      return Corrupt(where,
                     StrFormat("section count %u is outside [2, %u]", sections, kMaxSections));
    }
    toc_end_ = kHeaderBytes + kTocEntryBytes * sections;
    if (toc_end_ > size_) {
      return Corrupt(where, StrFormat("truncated: the table of contents of %u sections ends at "
                                      "byte %zu, the file has %zu bytes",
                                      sections, toc_end_, size_));
    }
    uint32_t crc = Crc32(data_, kHeaderCrcOffset);
    crc = Crc32(data_ + kHeaderBytes, toc_end_ - kHeaderBytes, crc);
    const uint32_t stored_crc = LoadLe<uint32_t>(data_ + kHeaderCrcOffset);
    if (crc != stored_crc) {
      return Corrupt(where, StrFormat("crc mismatch over header and table of contents (stored "
                                      "0x%08X, computed 0x%08X)",
                                      stored_crc, crc));
    }
    const uint64_t file_size = LoadLe<uint64_t>(data_ + kFileSizeOffset);
    if (file_size != size_) {
      return Corrupt(where, StrFormat("the file has %zu bytes, the header says %llu (truncated?)",
                                      size_, static_cast<ull>(file_size)));
    }
    toc_.resize(sections);
    return Status::Ok();
  }

  // Sections follow the TOC back to back, in TOC order, up to the end of the file.
  Status ReadToc() {
    uint64_t expected = toc_end_;
    for (size_t i = 0; i < toc_.size(); ++i) {
      toc_[i] = LoadTocEntry(data_ + kHeaderBytes + kTocEntryBytes * i);
      const TocEntry& e = toc_[i];
      const std::string where = StrFormat("TOC entry %zu (%s)", i, TagName(e.tag).c_str());
      if ((e.flags & ~kKnownFlags) != 0) {
        return Corrupt(where, StrFormat("unknown flags 0x%X", e.flags));
      }
      if (e.offset > size_) {
        return Corrupt(where, StrFormat("starts at byte %llu, past the end of the file (%zu bytes)",
                                        static_cast<ull>(e.offset), size_));
      }
      if (e.stored > size_ - e.offset) {
        return Corrupt(where,
                       StrFormat("offset %llu + size %llu runs past the end of the file "
                                 "(%zu bytes)",
                                 static_cast<ull>(e.offset), static_cast<ull>(e.stored), size_));
      }
      if (e.offset < expected) {
        return Corrupt(where, StrFormat("starts at byte %llu and overlaps what comes before it "
                                        "(ends at byte %llu)",
                                        static_cast<ull>(e.offset), static_cast<ull>(expected)));
      }
      if (e.offset > expected) {
        return Corrupt(where, StrFormat("starts at byte %llu, leaving a gap after byte %llu",
                                        static_cast<ull>(e.offset), static_cast<ull>(expected)));
      }
      if ((e.flags & kFlagZstd) == 0 && e.raw != e.stored) {
        return Corrupt(where,
                       StrFormat("stored uncompressed, but raw size %llu != stored size %llu",
                                 static_cast<ull>(e.raw), static_cast<ull>(e.stored)));
      }
      const uint64_t min_stored = e.raw / kMaxZstdExpansion + (e.raw % kMaxZstdExpansion != 0);
      if ((e.flags & kFlagZstd) != 0 && e.stored < min_stored) {
        return Corrupt(where, StrFormat("raw size %llu cannot come from %llu compressed bytes",
                                        static_cast<ull>(e.raw), static_cast<ull>(e.stored)));
      }
      expected = e.offset + e.stored;
    }
    if (expected != size_) {
      return Corrupt("file", StrFormat("%llu bytes after the last section",
                                       static_cast<ull>(size_ - expected)));
    }
    return Status::Ok();
  }

  // Checks entry `index` is a `tag` section of a plausible raw size, before
  // anything of it is read.
  Status Expect(size_t index, uint32_t tag, const std::string& label, uint64_t min_raw,
                uint64_t max_raw) const {
    if (index >= toc_.size()) {
      return Corrupt(
          label, StrFormat("missing: the table of contents has only %zu sections", toc_.size()));
    }
    const TocEntry& e = toc_[index];
    if (e.tag != tag) {
      return Corrupt(StrFormat("TOC entry %zu", index),
                     StrFormat("is %s, expected %s", TagName(e.tag).c_str(), label.c_str()));
    }
    if (e.raw < min_raw || e.raw > max_raw) {
      if (min_raw == max_raw) {
        return Corrupt(label, StrFormat("raw size %llu, the counts need %llu",
                                        static_cast<ull>(e.raw), static_cast<ull>(min_raw)));
      }
      return Corrupt(label, StrFormat("raw size %llu is outside [%llu, %llu] for the counts",
                                      static_cast<ull>(e.raw), static_cast<ull>(min_raw),
                                      static_cast<ull>(max_raw)));
    }
    if (!FitsSizeT(e.raw)) return Corrupt(label, "too large for this machine's address space");
    return Status::Ok();
  }

  // Verifies the crc and decompresses into exactly the declared raw size.
  Status Load(size_t index, const std::string& label, ByteReader* payload) {
    const TocEntry& e = toc_[index];
    const uint8_t* stored = data_ + e.offset;
    const auto stored_size = static_cast<size_t>(e.stored);
    const uint32_t crc = Crc32(stored, stored_size);
    if (crc != e.crc) {
      return Corrupt(label, StrFormat("crc mismatch (stored 0x%08X, computed 0x%08X)", e.crc, crc));
    }
    const auto raw = static_cast<size_t>(e.raw);
    if ((e.flags & kFlagZstd) == 0) {
      *payload = ByteReader(stored, stored_size);
      return Status::Ok();
    }
    const unsigned long long content = ZSTD_getFrameContentSize(stored, stored_size);
    if (content == ZSTD_CONTENTSIZE_ERROR) return Corrupt(label, "not a zstd frame");
    if (content == ZSTD_CONTENTSIZE_UNKNOWN) {
      return Corrupt(label, "zstd frame without a content size");
    }
    if (content != e.raw) {
      return Corrupt(label, StrFormat("zstd frame content size %llu != raw size %llu", content,
                                      static_cast<ull>(e.raw)));
    }
    const size_t frame = ZSTD_findFrameCompressedSize(stored, stored_size);
    if (ZSTD_isError(frame) || frame != stored_size) {
      return Corrupt(label, "stored bytes are not exactly one zstd frame");
    }
    if (!dctx_) dctx_.reset(ZSTD_createDCtx());
    if (!dctx_) return Status(StatusCode::kInternal, "bake: cannot create a zstd context");
    scratch_.resize(raw);
    const size_t n = ZSTD_decompressDCtx(dctx_.get(), scratch_.data(), raw, stored, stored_size);
    if (ZSTD_isError(n)) return Corrupt(label, StrFormat("zstd: %s", ZSTD_getErrorName(n)));
    if (n != raw) return Corrupt(label, StrFormat("decompressed %zu bytes, expected %zu", n, raw));
    *payload = ByteReader(scratch_.data(), raw);
    return Status::Ok();
  }

  // The payload must parse and be used up exactly.
  Status Finish(const ByteReader& r, const std::string& label) const {
    if (r.failed()) return Corrupt(label, "payload: " + r.error());
    if (r.remaining() != 0) {
      return Corrupt(label, StrFormat("%zu unused bytes at the end of the payload", r.remaining()));
    }
    return Status::Ok();
  }

  Status ParseMeta(Bake* bake) {
    const std::string label = "section META";
    RELIGHT_RETURN_IF_ERROR(Expect(0, kTagMeta, label, MetaBytes(0, 0), kMaxMetaBytes));
    ByteReader r(nullptr, 0);
    RELIGHT_RETURN_IF_ERROR(Load(0, label, &r));
    r.GetString(&bake->scene_name, kMaxNameBytes, "scene name");
    bake->white_luminance = r.Get<int32_t>("white luminance");
    for (int32_t& v : bake->camera.position) v = r.Get<int32_t>("camera position");
    for (int32_t& v : bake->camera.target) v = r.Get<int32_t>("camera target");
    bake->camera.fov_y = r.Get<int32_t>("camera fov_y");
    Counts& c = counts_;
    c.vertices = r.Get<uint32_t>("vertex count");
    c.triangles = r.Get<uint32_t>("triangle count");
    c.surfaces = r.Get<uint32_t>("surface count");
    c.grids = r.Get<uint32_t>("grid count");
    c.luminaires = r.Get<uint32_t>("luminaire count");
    if (r.failed()) return Finish(r, label);
    std::string e = CheckCounts(c.vertices, c.triangles, c.surfaces, c.grids, c.luminaires);
    if (!e.empty()) return Corrupt(label, e);
    c.grid_points.resize(c.grids);
    for (uint32_t g = 0; g < c.grids; ++g) {
      c.grid_points[g] = r.Get<uint32_t>("grid point count");
      e = CheckGridPointCount(c.grid_points[g]);
      if (!e.empty()) return Corrupt(label, StrFormat("grid %u: %s", g, e.c_str()));
    }
    RELIGHT_RETURN_IF_ERROR(Finish(r, label));
    e = CheckSceneHeader(*bake);
    if (!e.empty()) return Corrupt(label, e);
    return Status::Ok();
  }

  Status ParseMesh(Bake* bake) {
    const std::string label = "section MESH";
    const Counts& c = counts_;
    const uint64_t fixed = MeshBytesWithoutNames(c.vertices, c.triangles);
    RELIGHT_RETURN_IF_ERROR(Expect(1, kTagMesh, label, fixed + kStringBytes * c.surfaces,
                                   fixed + (kStringBytes + kMaxNameBytes) * c.surfaces));
    ByteReader r(nullptr, 0);
    RELIGHT_RETURN_IF_ERROR(Load(1, label, &r));
    BakeMesh& m = bake->mesh;
    const size_t v3 = 3 * size_t{c.vertices};
    r.GetPlanar(&m.positions, v3, 3, "positions");
    r.GetPlanar(&m.normals, v3, 3, "normals");
    r.GetPlanar(&m.albedo, v3, 3, "albedo");
    r.GetPlanar(&m.triangles, 3 * size_t{c.triangles}, 3, "triangles");
    r.GetPlanar(&m.triangle_surface, size_t{c.triangles}, 1, "triangle_surface");
    m.surface_names.resize(c.surfaces);
    for (std::string& name : m.surface_names) r.GetString(&name, kMaxNameBytes, "surface name");
    RELIGHT_RETURN_IF_ERROR(Finish(r, label));
    const std::string e = CheckMesh(m);
    if (!e.empty()) return Corrupt(label, e);
    return Status::Ok();
  }

  Status ParseGrid(uint32_t g, Bake* bake) {
    const std::string label = StrFormat("section GRID[%u]", g);
    const size_t index = 2 + g;
    const uint32_t points = counts_.grid_points[g];
    RELIGHT_RETURN_IF_ERROR(
        Expect(index, kTagGrid, label, GridBytes(1, points), GridBytes(kMaxNameBytes, points)));
    ByteReader r(nullptr, 0);
    RELIGHT_RETURN_IF_ERROR(Load(index, label, &r));
    BakeGrid grid;
    r.GetString(&grid.name, kMaxNameBytes, "name");
    grid.columns = r.Get<uint32_t>("columns");
    grid.rows = r.Get<uint32_t>("rows");
    r.GetPlanar(&grid.points, 3 * size_t{points}, 3, "points");
    r.GetPlanar(&grid.normals, 3 * size_t{points}, 3, "normals");
    RELIGHT_RETURN_IF_ERROR(Finish(r, label));
    const std::string e = CheckGrid(grid);
    if (!e.empty()) return Corrupt(label, e);
    bake->grids.push_back(std::move(grid));
    return Status::Ok();
  }

  Status ParseLuminaire(uint32_t l, Bake* bake) {
    const std::string label = StrFormat("section LUMI[%u]", l);
    const size_t index = 2 + counts_.grids + l;
    const bool tail = version_ >= 2;
    RELIGHT_RETURN_IF_ERROR(
        Expect(index, kTagLumi, label, LumiBytes(1, kMinLidSamples) + (tail ? kLumiTailFixedBytes : 0),
               LumiBytes(kMaxNameBytes, kMaxLidSamples) + (tail ? kMaxLumiTailBytes : 0)));
    ByteReader r(nullptr, 0);
    RELIGHT_RETURN_IF_ERROR(Load(index, label, &r));
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
    if (r.failed()) return Finish(r, label);
    if (samples < kMinLidSamples || samples > kMaxLidSamples) {
      return Corrupt(label, StrFormat("LID has %u samples, outside [%u, %u]", samples,
                                      kMinLidSamples, kMaxLidSamples));
    }
    if (samples > r.remaining() / 8) return Corrupt(label, "payload too short for the LID samples");
    lum.lid.candela.resize(samples);
    for (int64_t& cd : lum.lid.candela) cd = r.Get<int64_t>("LID");
    if (tail) RELIGHT_RETURN_IF_ERROR(ParseLuminaireTail(label, &r, &lum));
    RELIGHT_RETURN_IF_ERROR(Finish(r, label));
    const std::string e = CheckLuminaire(lum);
    if (!e.empty()) return Corrupt(label, e);
    bake->luminaires.push_back(std::move(lum));
    return Status::Ok();
  }

  // Version 2: orientation, console ranges, the (C, gamma) table and its SH
  // coefficients. Counts are checked before anything is allocated.
  Status ParseLuminaireTail(const std::string& label, ByteReader* r, BakeLuminaire* lum) {
    lum->yaw = r->Get<int32_t>("yaw");
    lum->roll = r->Get<int32_t>("roll");
    lum->pan_range = r->Get<int32_t>("pan range");
    lum->tilt_range = r->Get<int32_t>("tilt range");
    const uint32_t planes = r->Get<uint32_t>("LID plane count");
    const uint32_t gammas = r->Get<uint32_t>("LID gamma count");
    if (r->failed()) return Finish(*r, label);
    if ((planes == 0) != (gammas == 0) || planes > kMaxLidPlanes || gammas > kMaxLidGammas ||
        uint64_t{planes} * gammas > kMaxLidTableValues) {
      return Corrupt(label, StrFormat("LID table of %u planes x %u gammas is outside the limits "
                                      "(0 x 0, or [%u, %u] x [%u, %u] and at most %llu values)",
                                      planes, gammas, kMinLidPlanes, kMaxLidPlanes, kMinLidGammas,
                                      kMaxLidGammas, static_cast<ull>(kMaxLidTableValues)));
    }
    const uint64_t need = LumiTailBytes(planes, gammas, 0) - kLumiTailFixedBytes;
    if (need > r->remaining()) return Corrupt(label, "payload too short for the LID table");
    lum->lid.c_deg.resize(planes);
    lum->lid.gamma_deg.resize(gammas);
    lum->lid.table.resize(size_t{planes} * gammas);
    for (int32_t& v : lum->lid.c_deg) v = r->Get<int32_t>("LID C angle");
    for (int32_t& v : lum->lid.gamma_deg) v = r->Get<int32_t>("LID gamma angle");
    for (int64_t& v : lum->lid.table) v = r->Get<int64_t>("LID table");
    const uint32_t terms = r->Get<uint32_t>("LID SH coefficient count");
    if (r->failed()) return Finish(*r, label);
    if (terms > static_cast<uint32_t>(ShTermCount(kMaxShDegree)) || uint64_t{terms} * 8 > r->remaining()) {
      return Corrupt(label, StrFormat("LID has %u SH coefficients (at most %d, and the payload "
                                      "must hold them)",
                                      terms, ShTermCount(kMaxShDegree)));
    }
    lum->lid.sh.resize(terms);
    for (int64_t& v : lum->lid.sh) v = r->Get<int64_t>("LID SH coefficient");
    return Status::Ok();
  }

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
    const bool hierarchy_allowed = version_ >= kFirstVersionWithHierarchy;
    if (hierarchy_allowed && toc_.size() == expected + 2) {
      hierarchy_index_ = expected;
      // Fewer than 2 T nodes (bake_format.h); the node count itself is checked after loading.
      const uint64_t max_nodes = counts_.triangles == 0 ? 0 : 2 * uint64_t{counts_.triangles} - 1;
      RELIGHT_RETURN_IF_ERROR(Expect(expected, kTagHierarchy, "section HIER", HierBytes(1),
                                     HierBytes(max_nodes)));
      return Expect(expected + 1, kTagLinks, "section LINK", LinkBytes(0), LinkBytes(kMaxLinks));
    }
    if (toc_.size() != expected) {
      std::string also;
      if (hierarchy_allowed) {
        also = StrFormat(" (or %zu with HIER and LINK)", expected + 2);
      } else if (toc_.size() == expected + 2) {
        also = StrFormat(" (HIER and LINK need format version %u, the file has %u)",
                         kFirstVersionWithHierarchy, version_);
      }
      return Corrupt("table of contents", StrFormat("%zu sections, the counts need %zu%s",
                                                    toc_.size(), expected, also.c_str()));
    }
    return Status::Ok();
  }

  // DIRT (exact direct only) then BASE, per luminaire per receiver set. All
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
          if (lum.direct_mode == DirectMode::kExactDirect) {
            const std::string label = ReceiverLabel("DIRT", l, lum, s);
            if (pass == 0) {
              const uint64_t raw = DirectBytes(count);
              RELIGHT_RETURN_IF_ERROR(Expect(index, kTagDirect, label, raw, raw));
            } else {
              RELIGHT_RETURN_IF_ERROR(
                  ParseDirect(index, label, lum.direct_mode, count, &lum.receivers[s]));
            }
            ++index;
          }
          const std::string label = ReceiverLabel("BASE", l, lum, s);
          if (pass == 0) {
            const uint64_t raw = BasisBytes(terms, count);
            RELIGHT_RETURN_IF_ERROR(Expect(index, kTagBasis, label, raw, raw));
          } else {
            RELIGHT_RETURN_IF_ERROR(
                ParseBasis(index, label, lum.sh_degree, count, &lum.receivers[s]));
          }
          ++index;
        }
      }
    }
    return Status::Ok();
  }

  Status ParseDirect(size_t index, const std::string& label, DirectMode mode, uint32_t count,
                     BakeLightReceivers* rec) {
    ByteReader r(nullptr, 0);
    RELIGHT_RETURN_IF_ERROR(Load(index, label, &r));
    rec->geometry_scale.mantissa = r.Get<int32_t>("geometry_scale");
    rec->geometry_scale.exponent = r.Get<int32_t>("geometry_scale");
    r.GetPlanar(&rec->direction, 3 * size_t{count}, 3, "direction");
    r.GetPlanar(&rec->geometry, size_t{count}, 1, "geometry");
    RELIGHT_RETURN_IF_ERROR(Finish(r, label));
    const std::string e = CheckDirect(*rec, mode, count);
    if (!e.empty()) return Corrupt(label, e);
    return Status::Ok();
  }

  Status ParseBasis(size_t index, const std::string& label, int degree, uint32_t count,
                    BakeLightReceivers* rec) {
    ByteReader r(nullptr, 0);
    RELIGHT_RETURN_IF_ERROR(Load(index, label, &r));
    const auto terms = static_cast<size_t>(ShTermCount(degree));
    rec->basis_scale.resize(3 * terms);
    for (QuantScale& s : rec->basis_scale) {
      s.mantissa = r.Get<int32_t>("basis_scale");
      s.exponent = r.Get<int32_t>("basis_scale");
    }
    r.GetPlanar(&rec->basis, 3 * terms * count, 3, "basis");
    RELIGHT_RETURN_IF_ERROR(Finish(r, label));
    const std::string e = CheckBasis(*rec, degree, count);
    if (!e.empty()) return Corrupt(label, e);
    return Status::Ok();
  }

  // Loads a section that starts with its item count; its raw size must be
  // exactly what that count needs.
  Status LoadCounted(size_t index, const std::string& label, uint64_t (*bytes)(uint64_t),
                     const char* items, ByteReader* r, uint32_t* count) {
    RELIGHT_RETURN_IF_ERROR(Load(index, label, r));
    *count = r->Get<uint32_t>("count");
    if (r->failed()) return Finish(*r, label);
    const uint64_t raw = toc_[index].raw;
    if (bytes(*count) != raw) {
      return Corrupt(label, StrFormat("%u %s need %llu bytes, the section has %llu", *count, items,
                                      static_cast<ull>(bytes(*count)), static_cast<ull>(raw)));
    }
    return Status::Ok();
  }

  // HIER then LINK, after every DIRT and BASE.
  Status ParseHierarchy(Bake* bake) {
    BakeHierarchy h;
    std::string label = "section HIER";
    ByteReader r(nullptr, 0);
    uint32_t nodes = 0;
    RELIGHT_RETURN_IF_ERROR(LoadCounted(hierarchy_index_, label, HierBytes, "nodes", &r, &nodes));
    r.GetPlanar(&h.node_surface, nodes, 1, "node surface");
    r.GetPlanar(&h.node_parent, nodes, 1, "node parent");
    r.GetPlanar(&h.node_first_child, nodes, 1, "node first child");
    r.GetPlanar(&h.node_child_count, nodes, 1, "node child count");
    r.GetPlanar(&h.node_corner_count, nodes, 1, "node corner count");
    r.GetPlanar(&h.node_corners, size_t{nodes} * kBakeMaxNodeCorners, kBakeMaxNodeCorners,
                "node corners");
    r.GetPlanar(&h.node_area, nodes, 1, "node area");
    r.GetPlanar(&h.node_leaf_triangle, nodes, 1, "node leaf triangle");
    RELIGHT_RETURN_IF_ERROR(Finish(r, label));
    std::string e = CheckHierarchyNodes(h, bake->mesh);
    if (!e.empty()) return Corrupt(label, e);

    label = "section LINK";
    uint32_t links = 0;
    RELIGHT_RETURN_IF_ERROR(
        LoadCounted(hierarchy_index_ + 1, label, LinkBytes, "links", &r, &links));
    r.GetPlanar(&h.link_p, links, 1, "link p");
    r.GetPlanar(&h.link_q, links, 1, "link q");
    r.GetPlanar(&h.link_f_pq, links, 1, "link f_pq");
    r.GetPlanar(&h.link_f_qp, links, 1, "link f_qp");
    r.GetPlanar(&h.link_g_pq, 2 * size_t{links}, 2, "link g_pq");
    r.GetPlanar(&h.link_g_qp, 2 * size_t{links}, 2, "link g_qp");
    RELIGHT_RETURN_IF_ERROR(Finish(r, label));
    e = CheckHierarchyLinks(h);
    if (!e.empty()) return Corrupt(label, e);
    bake->hierarchy = std::move(h);
    return Status::Ok();
  }

  const uint8_t* data_;
  size_t size_;
  std::string name_;  // "'path'" or "(in memory)", for messages
  size_t toc_end_ = 0;
  uint32_t version_ = kVersion;
  std::vector<TocEntry> toc_;
  size_t hierarchy_index_ = 0;  // TOC index of HIER (LINK follows); 0: none
  Counts counts_;
  std::vector<uint8_t> scratch_;  // one decompressed section at a time
  std::unique_ptr<ZSTD_DCtx, DctxDeleter> dctx_;
};

}  // namespace

Status ParseBake(const uint8_t* data, size_t size, Bake* out) {
  if (data == nullptr && size != 0) return Status(StatusCode::kInvalidArgument, "bake: null data");
  return Parser(data, size, "(in memory)").Parse(out);
}

Status ReadBake(const std::string& path, Bake* out) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    const StatusCode code = err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError;
    return Status(code, StrFormat("bake '%s': %s", path.c_str(), std::strerror(err)));
  }
  struct stat st;
  std::string error;
  std::vector<uint8_t> bytes;
  if (::fstat(fd, &st) != 0) {
    error = std::strerror(errno);
  } else if (!S_ISREG(st.st_mode)) {
    error = "not a regular file";
  } else if (st.st_size < 0 || !FitsSizeT(st.st_size)) {
    error = "too large for this machine's address space";
  } else {
    bytes.resize(static_cast<size_t>(st.st_size));
    size_t done = 0;
    while (done < bytes.size() && error.empty()) {
      const ssize_t n = ::read(fd, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) error = std::strerror(errno);
      if (n == 0) error = "the file shrank while being read";
      if (n > 0) done += static_cast<size_t>(n);
    }
  }
  ::close(fd);
  if (!error.empty()) {
    return Status(StatusCode::kIoError, StrFormat("bake '%s': %s", path.c_str(), error.c_str()));
  }
  return Parser(bytes.data(), bytes.size(), "'" + path + "'").Parse(out);
}

}  // namespace relight
