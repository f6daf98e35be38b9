// Test side of docs/bake-format.md: split a bake file into its sections,
// change any field or payload, and join it again with correct crcs (or
// with the hostile layout a test asks for). Written from the spec, not from
// runtime/src, so the tests also check the reader against the document.
#pragma once

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include <zstd.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "bake_test_bake.h"
#include "relight/bake/bake.h"

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

// Random bytes behind valid crcs, `iterations` times, in a section drawn from
// `sections` (1 to 3 bytes; stored compressed and raw in turn). The reader
// must reject the file as corrupt or accept it, and whatever it accepts the
// writer must write (to `scratch_path`) and read back unchanged: both sides
// share one set of rules. Returns {accepted, rejected}.
inline std::pair<size_t, size_t> DamagePayloads(const Bytes& file,
                                                const std::vector<size_t>& sections,
                                                int iterations, uint32_t seed,
                                                const std::string& scratch_path) {
  std::mt19937 rng(seed);
  size_t accepted = 0, rejected = 0;
  for (int iter = 0; iter < iterations; ++iter) {
    const size_t pick = std::uniform_int_distribution<size_t>(0, sections.size() - 1)(rng);
    const int edits = std::uniform_int_distribution<int>(1, 3)(rng);
    const Bytes bad = EditPayload(
        file, sections[pick],
        [&](Bytes* p) {
          for (int e = 0; e < edits && !p->empty(); ++e) {
            const size_t at = std::uniform_int_distribution<size_t>(0, p->size() - 1)(rng);
            (*p)[at] = static_cast<uint8_t>(rng());
          }
        },
        iter % 2 == 0);
    Bake out;
    const Status st = ParseBake(bad.data(), bad.size(), &out);
    if (!st.ok()) {
      ++rejected;
      EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
      continue;
    }
    ++accepted;
    const Status written = WriteBake(out, scratch_path);
    EXPECT_TRUE(written.ok()) << "iteration " << iter << ": " << written.ToString();
    Bake again;
    EXPECT_TRUE(ReadBake(scratch_path, &again).ok());
    ExpectBakesEqual(out, again);
    if (::testing::Test::HasFailure()) break;
  }
  return {accepted, rejected};
}

inline Bytes ReadFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline bool Contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

// A directory of its own, with MakeBake(7) (which has a hierarchy) written to
// good.rlb: bake_ and its bytes file_.
class BakeFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/bake_file_test.XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
    bake_ = MakeBake(7);
    ASSERT_TRUE(WriteBake(bake_, Path("good.rlb")).ok());
    file_ = ReadFileBytes(Path("good.rlb"));
    ASSERT_GT(file_.size(), kHeaderBytes);
  }
  void TearDown() override {
    ::chmod(dir_.c_str(), 0755);
    std::filesystem::remove_all(dir_);
  }
  std::string Path(const std::string& name) const { return dir_ + "/" + name; }
  // Files in the test directory: a failed write must leave no temporary behind.
  size_t FileCount() const {
    size_t n = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir_)) n += entry.exists() ? 1 : 0;
    return n;
  }

  // A copy of bake_ broken one way, and what WriteBake must say about it.
  struct Spoiled {
    const char* what;
    std::function<void(Bake*)> spoil;
  };
  // WriteBake refuses each as kInvalidArgument ("bake: " ... `what` ...) and
  // leaves good.rlb as it was, with nothing beside it.
  void ExpectWriteRejects(const std::vector<Spoiled>& cases) {
    const std::string path = Path("good.rlb");
    for (const Spoiled& c : cases) {
      SCOPED_TRACE(c.what);
      Bake bad = bake_;
      c.spoil(&bad);
      const Status st = WriteBake(bad, path);
      EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << st.ToString();
      EXPECT_EQ(st.message().rfind("bake: ", 0), 0u) << st.message();
      EXPECT_TRUE(Contains(st.message(), c.what)) << st.message();
      EXPECT_EQ(ReadFileBytes(path), file_);
      EXPECT_EQ(FileCount(), 1u);
    }
  }

  std::string dir_;
  Bake bake_;
  Bytes file_;
};

}  // namespace relight::bake_test
