// Test side of docs/bake-format.md: split a bake file into its sections,
// change any field or payload, and join it again with correct crcs (or
// with the hostile layout a test asks for). Written from the spec, not from
// runtime/src, so the tests also check the reader against the document.
#pragma once

#include <gtest/gtest.h>
#include <zlib.h>
#include <zstd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <vector>

namespace relight::bake_test {

using Bytes = std::vector<uint8_t>;

constexpr size_t kHeaderBytes = 28;
constexpr size_t kTocEntryBytes = 36;

// --- Little-endian fields, as docs/bake-format.md specifies them.
template <typename T>
T GetLe(const uint8_t* p) {
  uint64_t v = 0;
  for (size_t b = 0; b < sizeof(T); ++b) v |= uint64_t{p[b]} << (8 * b);
  return static_cast<T>(v);
}
template <typename T>
void PutLe(uint8_t* p, T value) {
  const auto v = static_cast<uint64_t>(value);
  for (size_t b = 0; b < sizeof(T); ++b) p[b] = static_cast<uint8_t>(v >> (8 * b));
}
inline uint32_t Crc(const uint8_t* p, size_t n, uint32_t crc = 0) {
  return static_cast<uint32_t>(crc32(crc, p, static_cast<uInt>(n)));
}
inline uint32_t Tag(const char* s) { return GetLe<uint32_t>(reinterpret_cast<const uint8_t*>(s)); }

// A bake file split into its sections, trusting the file (test side only).
struct Section {
  uint32_t tag = 0, flags = 0;
  uint64_t offset = 0, stored = 0, raw = 0;
  uint32_t crc = 0;
  Bytes bytes;
};
struct Container {
  uint32_t version = 1;
  std::vector<Section> sections;
};

inline Container Split(const Bytes& file) {
  Container c;
  c.version = GetLe<uint32_t>(&file[8]);
  const uint32_t n = GetLe<uint32_t>(&file[12]);
  for (uint32_t i = 0; i < n; ++i) {
    const uint8_t* p = &file[kHeaderBytes + kTocEntryBytes * i];
    Section s;
    s.tag = GetLe<uint32_t>(p);
    s.flags = GetLe<uint32_t>(p + 4);
    s.offset = GetLe<uint64_t>(p + 8);
    s.stored = GetLe<uint64_t>(p + 16);
    s.raw = GetLe<uint64_t>(p + 24);
    s.crc = GetLe<uint32_t>(p + 32);
    s.bytes.assign(file.begin() + static_cast<ptrdiff_t>(s.offset),
                   file.begin() + static_cast<ptrdiff_t>(s.offset + s.stored));
    c.sections.push_back(std::move(s));
  }
  return c;
}

// Offsets, stored sizes and crcs from the bytes: a well-formed layout.
inline void Relayout(Container* c) {
  uint64_t offset = kHeaderBytes + kTocEntryBytes * c->sections.size();
  for (Section& s : c->sections) {
    s.offset = offset;
    s.stored = s.bytes.size();
    s.crc = Crc(s.bytes.data(), s.bytes.size());
    offset += s.stored;
  }
}

// Header and TOC from the fields as they are (hostile ones included), a
// correct header crc, then the section bytes back to back.
inline Bytes Join(const Container& c) {
  Bytes file(kHeaderBytes + kTocEntryBytes * c.sections.size(), 0);
  std::memcpy(file.data(), "RELIGHT\0", 8);
  PutLe(&file[8], c.version);
  PutLe(&file[12], static_cast<uint32_t>(c.sections.size()));
  for (size_t i = 0; i < c.sections.size(); ++i) {
    const Section& s = c.sections[i];
    uint8_t* p = &file[kHeaderBytes + kTocEntryBytes * i];
    PutLe(p, s.tag);
    PutLe(p + 4, s.flags);
    PutLe(p + 8, s.offset);
    PutLe(p + 16, s.stored);
    PutLe(p + 24, s.raw);
    PutLe(p + 32, s.crc);
  }
  for (const Section& s : c.sections) file.insert(file.end(), s.bytes.begin(), s.bytes.end());
  PutLe(&file[16], static_cast<uint64_t>(file.size()));
  const uint32_t crc =
      Crc(&file[kHeaderBytes], kTocEntryBytes * c.sections.size(), Crc(file.data(), 24));
  PutLe(&file[24], crc);
  return file;
}

inline Bytes Payload(const Section& s) {
  if ((s.flags & 1) == 0) return s.bytes;
  Bytes raw(static_cast<size_t>(ZSTD_getFrameContentSize(s.bytes.data(), s.bytes.size())));
  const size_t n = ZSTD_decompress(raw.data(), raw.size(), s.bytes.data(), s.bytes.size());
  EXPECT_EQ(n, raw.size());
  return raw;
}

inline void SetPayload(Section* s, const Bytes& raw, bool compress) {
  s->raw = raw.size();
  s->flags = compress ? 1u : 0u;
  s->bytes = raw;
  if (compress) {
    s->bytes.resize(ZSTD_compressBound(raw.size()));
    s->bytes.resize(ZSTD_compress(s->bytes.data(), s->bytes.size(), raw.data(), raw.size(), 3));
  }
}

// Planar delta arrays (docs/bake-format.md "Arrays").
template <typename T>
std::vector<T> DecodePlanar(const Bytes& b, size_t at, size_t n, size_t stride) {
  std::vector<T> out(n);
  for (size_t i = 0; i < n; ++i) {
    uint64_t d = 0;
    for (size_t k = 0; k < sizeof(T); ++k) d |= uint64_t{b[at + k * n + i]} << (8 * k);
    const uint64_t prev = i >= stride ? static_cast<uint64_t>(out[i - stride]) : 0;
    out[i] = static_cast<T>(prev + d);
  }
  return out;
}
template <typename T>
void EncodePlanar(const std::vector<T>& v, size_t stride, Bytes* b, size_t at) {
  const size_t n = v.size();
  for (size_t i = 0; i < n; ++i) {
    const uint64_t prev = i >= stride ? static_cast<uint64_t>(v[i - stride]) : 0;
    const uint64_t d = static_cast<uint64_t>(v[i]) - prev;
    for (size_t k = 0; k < sizeof(T); ++k) {
      (*b)[at + k * n + i] = static_cast<uint8_t>(d >> (8 * k));
    }
  }
}

// Rewrites one section's payload (stored raw or compressed) into a file
// that is otherwise well-formed, crcs included.
inline Bytes EditPayload(const Bytes& file, size_t section, const std::function<void(Bytes*)>& edit,
                         bool compress = false) {
  Container c = Split(file);
  Bytes raw = Payload(c.sections[section]);
  edit(&raw);
  SetPayload(&c.sections[section], raw, compress);
  Relayout(&c);
  return Join(c);
}

}  // namespace relight::bake_test
