// The bake container (docs/bake-format.md "File layout"), shared by the
// reader and the writer: the header, the table of contents, a crc32 per
// section and over header + TOC, zstd compression. What a section holds is
// its own file's business (bake_sections.h); the file itself, bake_file_io.h.
// Private to the bake layer.
#pragma once

#include <zstd.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bake_bytes.h"
#include "bake_file_io.h"
#include "bake_format.h"
#include "relight/base/status.h"

namespace relight::bake_format {

// "META", or 0x... for a tag that is not four capitals (for messages).
std::string TagName(uint32_t tag);

template <typename T>
bool FitsSizeT(T v) {
  return static_cast<uint64_t>(static_cast<size_t>(v)) == static_cast<uint64_t>(v);
}

struct DctxDeleter {
  void operator()(ZSTD_DCtx* d) const { ZSTD_freeDCtx(d); }
};
struct CctxDeleter {
  void operator()(ZSTD_CCtx* c) const { ZSTD_freeCCtx(c); }
};

// Reads a container from bytes in memory or from an open file, trusting
// nothing: Open() checks
// magic, version, crc over header and TOC, sizes and layout before any
// section is read; Expect() a section's tag and raw size before Load()
// checks its crc and decompresses it. Errors are kCorrupt "bake NAME: where: what".
class ContainerReader {
 public:
  ContainerReader(const uint8_t* data, size_t size, std::string name)
      : data_(data), size_(size), name_(std::move(name)) {}
  // From a file, one section at a time: what is held at once is the header
  // and TOC, one section as stored and one decompressed, never the file.
  // `file` must outlive the reader.
  ContainerReader(const ReadOnlyFile* file, std::string name)
      : size_(file->size()), name_(std::move(name)), file_(file) {}

  // Header and table of contents. kCorrupt, or kUnsupported for a newer version.
  Status Open() {
    RELIGHT_RETURN_IF_ERROR(ReadHeader());
    return ReadToc();
  }
  uint32_t version() const { return version_; }
  size_t section_count() const { return toc_.size(); }
  uint64_t raw_size(size_t index) const { return toc_[index].raw; }
  // The tag of entry `index`, 0 past the end.
  uint32_t tag(size_t index) const { return index < toc_.size() ? toc_[index].tag : 0; }

  Status Corrupt(const std::string& where, const std::string& what) const;
  // Checks entry `index` is a `tag` section of a plausible raw size, before
  // anything of it is read.
  Status Expect(size_t index, uint32_t tag, const std::string& label, uint64_t min_raw,
                uint64_t max_raw) const;
  // Verifies the crc and decompresses into exactly the declared raw size;
  // `payload` reads it until the next Load.
  Status Load(size_t index, const std::string& label, ByteReader* payload);
  // Loads a section that starts with its item count; its raw size must be
  // exactly bytes(count).
  Status LoadCounted(size_t index, const std::string& label, uint64_t (*bytes)(uint64_t),
                     const char* items, ByteReader* r, uint32_t* count);
  // The payload must parse and be used up exactly.
  Status Finish(const ByteReader& r, const std::string& label) const;

 private:
  Status ReadHeader();
  Status ReadToc();
  // `n` bytes at `offset`: in place in memory, or read from the file into
  // `buffer`. The caller has checked the range lies within the file.
  Status Fetch(uint64_t offset, size_t n, std::vector<uint8_t>* buffer, const std::string& label,
               const uint8_t** bytes) const;

  const uint8_t* data_ = nullptr;  // the whole container (memory), or null (file)
  size_t size_;
  std::string name_;  // "'path'" or "(in memory)", for messages
  size_t toc_end_ = 0;
  uint32_t version_ = kVersion;
  std::vector<TocEntry> toc_;
  const ReadOnlyFile* file_ = nullptr;
  const uint8_t* head_ = nullptr;  // header + TOC: in data_, or in head_bytes_
  std::vector<uint8_t> head_bytes_;
  std::vector<uint8_t> stored_;   // one section as stored (file only)
  std::vector<uint8_t> scratch_;  // one decompressed section at a time
  std::unique_ptr<ZSTD_DCtx, DctxDeleter> dctx_;
};

// Appends sections to an open file (compressed when that is smaller, each
// with its crc) and remembers their TOC entries. Add returns false with
// errno set on an I/O failure.
class SectionSink {
 public:
  SectionSink(int fd, uint64_t first_offset);

  // Stores `raw` compressed when that is smaller, else as is.
  bool Add(uint32_t tag, const std::vector<uint8_t>& raw);

  uint64_t end() const { return offset_; }
  const std::vector<TocEntry>& toc() const { return toc_; }

 private:
  int fd_;
  uint64_t offset_;
  std::unique_ptr<ZSTD_CCtx, CctxDeleter> cctx_;
  std::vector<uint8_t> packed_;
  std::vector<TocEntry> toc_;
};

// Header and TOC bytes for `toc`, crc included.
std::vector<uint8_t> EncodeHeader(uint32_t version, const std::vector<TocEntry>& toc,
                                  uint64_t file_size);

}  // namespace relight::bake_format
