// WriteBake: validate, serialise every section (docs/bake-format.md), zstd
// compress, and write atomically: a temporary file beside the target,
// fsync, rename over the target. Any failure removes the temporary file and
// leaves the target as it was.
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

namespace relight {
namespace {

using namespace bake_format;  // NOLINT: the layout constants read better bare

Status Invalid(const std::string& where, const std::string& what) {
  return Status(StatusCode::kInvalidArgument, "bake: " + where + ": " + what);
}

std::string LuminaireLabel(size_t index, const BakeLuminaire& lum) {
  return StrFormat("luminaire %zu '%s'", index, lum.name.c_str());
}

std::string SetLabel(const Bake& bake, uint32_t set) {
  if (set == 0) return "receiver set 0 (vertices)";
  return StrFormat("receiver set %u (grid %u '%s')", set, set - 1,
                   bake.grids[set - 1].name.c_str());
}

// Every rule of bake_check.h, so WriteBake never writes a file ReadBake rejects.
Status Validate(const Bake& bake) {
  std::string e = CheckSceneHeader(bake);
  if (!e.empty()) return Invalid("scene", e);
  e = CheckMesh(bake.mesh);
  if (!e.empty()) return Invalid("mesh", e);
  e = CheckCounts(bake.mesh.vertex_count(), bake.mesh.triangle_count(),
                  bake.mesh.surface_names.size(), bake.grids.size(), bake.luminaires.size());
  if (!e.empty()) return Invalid("counts", e);
  std::vector<const std::string*> names;
  for (size_t g = 0; g < bake.grids.size(); ++g) {
    e = CheckGrid(bake.grids[g]);
    if (!e.empty()) return Invalid(StrFormat("grid %zu", g), e);
    names.push_back(&bake.grids[g].name);
  }
  e = CheckUniqueNames(names, "grid");
  if (!e.empty()) return Invalid("grids", e);
  names.clear();
  for (size_t l = 0; l < bake.luminaires.size(); ++l) {
    const BakeLuminaire& lum = bake.luminaires[l];
    const std::string label = LuminaireLabel(l, lum);
    e = CheckLuminaire(lum);
    if (!e.empty()) return Invalid(StrFormat("luminaire %zu", l), e);
    names.push_back(&lum.name);
    if (lum.receivers.size() != bake.receiver_set_count()) {
      return Invalid(label,
                     StrFormat("has %zu receiver sets, expected 1 + %zu grids = %u",
                               lum.receivers.size(), bake.grids.size(), bake.receiver_set_count()));
    }
    for (uint32_t s = 0; s < bake.receiver_set_count(); ++s) {
      const uint32_t count = bake.receiver_count(s);
      e = CheckDirect(lum.receivers[s], lum.direct_mode, count);
      if (e.empty()) e = CheckBasis(lum.receivers[s], lum.sh_degree, count);
      if (!e.empty()) return Invalid(label + ", " + SetLabel(bake, s), e);
    }
  }
  e = CheckUniqueNames(names, "luminaire");
  if (!e.empty()) return Invalid("luminaires", e);
  if (bake.hierarchy) {
    e = CheckHierarchyNodes(*bake.hierarchy, bake.mesh);
    if (!e.empty()) return Invalid("hierarchy nodes", e);
    e = CheckHierarchyLinks(*bake.hierarchy);
    if (!e.empty()) return Invalid("hierarchy links", e);
  }
  return Status::Ok();
}

// --- Section payloads, field order as in docs/bake-format.md.

void EncodeMeta(const Bake& bake, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  w.PutString(bake.scene_name);
  w.Put(bake.white_luminance);
  for (int32_t v : bake.camera.position) w.Put(v);
  for (int32_t v : bake.camera.target) w.Put(v);
  w.Put(bake.camera.fov_y);
  w.Put(bake.mesh.vertex_count());
  w.Put(bake.mesh.triangle_count());
  w.Put(static_cast<uint32_t>(bake.mesh.surface_names.size()));
  w.Put(static_cast<uint32_t>(bake.grids.size()));
  w.Put(static_cast<uint32_t>(bake.luminaires.size()));
  for (const BakeGrid& g : bake.grids) w.Put(g.point_count());
}

void EncodeMesh(const BakeMesh& mesh, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  w.PutPlanar(mesh.positions, 3);
  w.PutPlanar(mesh.normals, 3);
  w.PutPlanar(mesh.albedo, 3);
  w.PutPlanar(mesh.triangles, 3);
  w.PutPlanar(mesh.triangle_surface, 1);
  for (const std::string& name : mesh.surface_names) w.PutString(name);
}

void EncodeGrid(const BakeGrid& grid, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  w.PutString(grid.name);
  w.Put(grid.columns);
  w.Put(grid.rows);
  w.PutPlanar(grid.points, 3);
  w.PutPlanar(grid.normals, 3);
}

void EncodeLuminaire(const BakeLuminaire& lum, std::vector<uint8_t>* out) {
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
}

void PutScale(ByteWriter* w, QuantScale s) {
  w->Put(s.mantissa);
  w->Put(s.exponent);
}

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

void EncodeHierarchyNodes(const BakeHierarchy& h, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  w.Put(h.node_count());
  w.PutPlanar(h.node_surface, 1);
  w.PutPlanar(h.node_parent, 1);
  w.PutPlanar(h.node_first_child, 1);
  w.PutPlanar(h.node_child_count, 1);
  w.PutPlanar(h.node_corner_count, 1);
  w.PutPlanar(h.node_corners, kBakeMaxNodeCorners);
  w.PutPlanar(h.node_area, 1);
  w.PutPlanar(h.node_leaf_triangle, 1);
}

void EncodeHierarchyLinks(const BakeHierarchy& h, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  w.Put(h.link_count());
  w.PutPlanar(h.link_p, 1);
  w.PutPlanar(h.link_q, 1);
  w.PutPlanar(h.link_f_pq, 1);
  w.PutPlanar(h.link_f_qp, 1);
  w.PutPlanar(h.link_g_pq, 2);
  w.PutPlanar(h.link_g_qp, 2);
}

uint32_t SectionCount(const Bake& bake) {
  uint32_t n = 2 + static_cast<uint32_t>(bake.grids.size() + bake.luminaires.size());
  for (const BakeLuminaire& lum : bake.luminaires) {
    const uint32_t per_set = lum.direct_mode == DirectMode::kExactDirect ? 2 : 1;
    n += per_set * bake.receiver_set_count();
  }
  return n + (bake.hierarchy ? 2 : 0);
}

Status IoError(const std::string& path, const char* what, int err) {
  return Status(StatusCode::kIoError,
                StrFormat("bake '%s': %s: %s", path.c_str(), what, std::strerror(err)));
}

// pwrite() may write less than asked and be interrupted; loop until done.
// Returns false with errno set.
bool WriteAt(int fd, const uint8_t* data, size_t size, uint64_t offset) {
  while (size > 0) {
    const size_t chunk = size < (size_t{1} << 30) ? size : (size_t{1} << 30);
    const ssize_t n = ::pwrite(fd, data, chunk, static_cast<off_t>(offset));
    if (n < 0 && errno == EINTR) continue;
    if (n == 0) errno = EIO;
    if (n <= 0) return false;
    data += n;
    size -= static_cast<size_t>(n);
    offset += static_cast<uint64_t>(n);
  }
  return true;
}

struct CctxDeleter {
  void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};

// Appends sections to an open file and remembers their TOC entries.
class SectionSink {
 public:
  SectionSink(int fd, uint64_t first_offset) : fd_(fd), offset_(first_offset) {
    cctx_.reset(ZSTD_createCCtx());
    if (cctx_) {
      ZSTD_CCtx_setParameter(cctx_.get(), ZSTD_c_compressionLevel, kZstdLevel);
      // Multithreaded compression only speeds large sections; a zstd built
      // without threads refuses the parameter and compresses on one thread.
      (void)ZSTD_CCtx_setParameter(cctx_.get(), ZSTD_c_nbWorkers, kZstdWorkers);
    }
  }

  // Stores `raw` compressed when that is smaller, else as is.
  bool Add(uint32_t tag, const std::vector<uint8_t>& raw) {
    TocEntry e;
    e.tag = tag;
    e.offset = offset_;
    e.raw = raw.size();
    const uint8_t* stored = raw.data();
    size_t stored_size = raw.size();
    if (cctx_ && !raw.empty()) {
      packed_.resize(ZSTD_compressBound(raw.size()));
      const size_t n =
          ZSTD_compress2(cctx_.get(), packed_.data(), packed_.size(), raw.data(), raw.size());
      // A compression error only costs size: the raw bytes are a valid section.
      if (!ZSTD_isError(n) && n < raw.size()) {
        e.flags = kFlagZstd;
        stored = packed_.data();
        stored_size = n;
      }
    }
    e.stored = stored_size;
    e.crc = Crc32(stored, stored_size);
    if (!WriteAt(fd_, stored, stored_size, offset_)) return false;
    offset_ += stored_size;
    toc_.push_back(e);
    return true;
  }

  uint64_t end() const { return offset_; }
  const std::vector<TocEntry>& toc() const { return toc_; }

 private:
  int fd_;
  uint64_t offset_;
  std::unique_ptr<ZSTD_CCtx, CctxDeleter> cctx_;
  std::vector<uint8_t> packed_;
  std::vector<TocEntry> toc_;
};

std::vector<uint8_t> EncodeHeader(uint32_t version, const std::vector<TocEntry>& toc,
                                  uint64_t file_size) {
  std::vector<uint8_t> h(kHeaderBytes + kTocEntryBytes * toc.size(), 0);
  std::memcpy(h.data(), kMagic, sizeof(kMagic));
  StoreLe(h.data() + kVersionOffset, version);
  StoreLe(h.data() + kSectionCountOffset, static_cast<uint32_t>(toc.size()));
  StoreLe(h.data() + kFileSizeOffset, file_size);
  for (size_t i = 0; i < toc.size(); ++i) {
    StoreTocEntry(h.data() + kHeaderBytes + kTocEntryBytes * i, toc[i]);
  }
  uint32_t crc = Crc32(h.data(), kHeaderCrcOffset);
  crc = Crc32(h.data() + kHeaderBytes, h.size() - kHeaderBytes, crc);
  StoreLe(h.data() + kHeaderCrcOffset, crc);
  return h;
}

// Writes every section in TOC order behind the space for the header and TOC,
// then them. Returns false with errno set on an I/O failure.
bool WriteSections(const Bake& bake, int fd, std::vector<BakeSectionSize>* sizes) {
  const uint32_t sections = SectionCount(bake);
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
    ok = ok && add(kTagLumi, [&](std::vector<uint8_t>* o) { EncodeLuminaire(lum, o); });
  }
  for (const BakeLuminaire& lum : bake.luminaires) {
    for (const BakeLightReceivers& rec : lum.receivers) {
      if (lum.direct_mode == DirectMode::kExactDirect) {
        ok = ok && add(kTagDirect, [&](std::vector<uint8_t>* o) { EncodeDirect(rec, o); });
      }
      ok = ok && add(kTagBasis, [&](std::vector<uint8_t>* o) { EncodeBasis(rec, o); });
    }
  }
  if (bake.hierarchy) {
    const BakeHierarchy& h = *bake.hierarchy;
    ok = ok && add(kTagHierarchy, [&](std::vector<uint8_t>* o) { EncodeHierarchyNodes(h, o); }) &&
         add(kTagLinks, [&](std::vector<uint8_t>* o) { EncodeHierarchyLinks(h, o); });
  }
  if (!ok) return false;
  RELIGHT_CHECK(sink.toc().size() == sections);
  const uint32_t version = bake.hierarchy ? kFirstVersionWithHierarchy : kVersionWithoutHierarchy;
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

// Makes the rename itself durable. Best effort: the new file is already in
// place when this runs, so a failure here is not reported as one.
void SyncDirectoryOf(const std::string& path) {
  const size_t slash = path.rfind('/');
  const std::string dir = slash == std::string::npos ? "."
                          : slash == 0               ? "/"
                                                     : path.substr(0, slash);
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);
  ::close(fd);
}

}  // namespace

Status WriteBake(const Bake& bake, const std::string& path, std::vector<BakeSectionSize>* sizes) {
  if (path.empty()) return Status(StatusCode::kInvalidArgument, "bake: empty path");
  RELIGHT_RETURN_IF_ERROR(Validate(bake));

  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return IoError(path, ("cannot create '" + tmp + "'").c_str(), errno);

  const char* failed = nullptr;
  if (!WriteSections(bake, fd, sizes)) {
    failed = "write failed";
  } else if (::fsync(fd) != 0) {
    failed = "fsync failed";
  }
  int err = failed ? errno : 0;
  if (::close(fd) != 0 && !failed) {
    failed = "close failed";
    err = errno;
  }
  if (!failed && ::rename(tmp.c_str(), path.c_str()) != 0) {
    failed = "rename failed";
    err = errno;
  }
  if (failed) {
    ::unlink(tmp.c_str());
    return IoError(path, failed, err);
  }
  SyncDirectoryOf(path);
  return Status::Ok();
}

}  // namespace relight
