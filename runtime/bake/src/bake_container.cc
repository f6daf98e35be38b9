// The bake container (see bake_container.h).
#include "bake_container.h"

#include <cstring>

namespace relight::bake_format {

using ull = unsigned long long;

std::string TagName(uint32_t tag) {
  char s[5] = {};
  for (int i = 0; i < 4; ++i) {
    const char c = static_cast<char>(tag >> (8 * i));
    if ((c < 'A' || c > 'Z') && (c < '0' || c > '9')) return StrFormat("0x%08X", tag);  // CPC8
    s[i] = c;
  }
  return s;
}

Status ContainerReader::Corrupt(const std::string& where, const std::string& what) const {
  return Status(StatusCode::kCorrupt, "bake " + name_ + ": " + where + ": " + what);
}

Status ContainerReader::Fetch(uint64_t offset, size_t n, std::vector<uint8_t>* buffer,
                              const std::string& label, const uint8_t** bytes) const {
  if (file_ == nullptr) {
    *bytes = data_ + offset;
    return Status::Ok();
  }
  buffer->resize(n);
  const std::string error = file_->ReadAt(offset, n, buffer->data());
  if (!error.empty()) return Status(StatusCode::kIoError, "bake " + name_ + ": " + label + ": " + error);
  *bytes = buffer->data();
  return Status::Ok();
}

Status ContainerReader::ReadHeader() {
  const char* where = "header";
  if (size_ == 0) return Corrupt(where, "empty file");
  RELIGHT_RETURN_IF_ERROR(Fetch(0, size_ < kHeaderBytes ? size_ : kHeaderBytes, &head_bytes_, where, &head_));
  const size_t have = size_ < sizeof(kMagic) ? size_ : sizeof(kMagic);
  if (std::memcmp(head_, kMagic, have) != 0) {
    return Corrupt(where, "bad magic, not a relight bake");
  }
  if (size_ < kHeaderBytes) {
    return Corrupt(
        where, StrFormat("truncated: %zu bytes, the header alone is %zu", size_, kHeaderBytes));
  }
  const uint32_t version = LoadLe<uint32_t>(head_ + kVersionOffset);
  if (version > kVersion) {
    // Only magic and version are promised to stay put across versions.
    return Status(StatusCode::kUnsupported,
                  StrFormat("bake %s: format version %u is newer than this build reads (%u)",
                            name_.c_str(), version, kVersion));
  }
  if (version == 0) return Corrupt(where, "format version 0");
  version_ = version;
  const uint32_t sections = LoadLe<uint32_t>(head_ + kSectionCountOffset);
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
  RELIGHT_RETURN_IF_ERROR(Fetch(0, toc_end_, &head_bytes_, where, &head_));
  uint32_t crc = Crc32(head_, kHeaderCrcOffset);
  crc = Crc32(head_ + kHeaderBytes, toc_end_ - kHeaderBytes, crc);
  const uint32_t stored_crc = LoadLe<uint32_t>(head_ + kHeaderCrcOffset);
  if (crc != stored_crc) {
    return Corrupt(where, StrFormat("crc mismatch over header and table of contents (stored "
                                    "0x%08X, computed 0x%08X)",
                                    stored_crc, crc));
  }
  const uint64_t file_size = LoadLe<uint64_t>(head_ + kFileSizeOffset);
  if (file_size != size_) {
    return Corrupt(where, StrFormat("the file has %zu bytes, the header says %llu (truncated?)",
                                    size_, static_cast<ull>(file_size)));
  }
  toc_.resize(sections);
  return Status::Ok();
}

// Sections follow the TOC back to back, in TOC order, up to the end of the file.
Status ContainerReader::ReadToc() {
  uint64_t expected = toc_end_;
  for (size_t i = 0; i < toc_.size(); ++i) {
    toc_[i] = LoadTocEntry(head_ + kHeaderBytes + kTocEntryBytes * i);
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

Status ContainerReader::Expect(size_t index, uint32_t tag, const std::string& label, uint64_t min_raw,
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

Status ContainerReader::Load(size_t index, const std::string& label, ByteReader* payload) {
  const TocEntry& e = toc_[index];
  const auto stored_size = static_cast<size_t>(e.stored);
  const uint8_t* stored = nullptr;
  RELIGHT_RETURN_IF_ERROR(Fetch(e.offset, stored_size, &stored_, label, &stored));
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

Status ContainerReader::Finish(const ByteReader& r, const std::string& label) const {
  if (r.failed()) return Corrupt(label, "payload: " + r.error());
  if (r.remaining() != 0) {
    return Corrupt(label, StrFormat("%zu unused bytes at the end of the payload", r.remaining()));
  }
  return Status::Ok();
}

// Loads a section that starts with its item count; its raw size must be
// exactly what that count needs.
Status ContainerReader::LoadCounted(size_t index, const std::string& label, uint64_t (*bytes)(uint64_t),
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

SectionSink::SectionSink(int fd, uint64_t first_offset) : fd_(fd), offset_(first_offset) {
  cctx_.reset(ZSTD_createCCtx());
  if (cctx_) {
    ZSTD_CCtx_setParameter(cctx_.get(), ZSTD_c_compressionLevel, kZstdLevel);
    // Multithreaded compression only speeds large sections; a zstd built
    // without threads refuses the parameter and compresses on one thread.
    (void)ZSTD_CCtx_setParameter(cctx_.get(), ZSTD_c_nbWorkers, kZstdWorkers);
  }
}

bool SectionSink::Add(uint32_t tag, const std::vector<uint8_t>& raw) {
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

}  // namespace relight::bake_format
