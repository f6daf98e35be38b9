// Bake file round trips, and a reader that survives every damaged or hostile
// file: truncation at every offset, bit flips, lying headers and payloads.
// Hostile files are built with bake_file_edit.h, written from
// docs/bake-format.md, so the tests also check the reader against the spec.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <new>
#include <random>
#include <string>
#include <vector>

#include "bake_file_edit.h"
#include "bake_test_bake.h"
#include "relight/bake/bake.h"
#include "relight/base/sh_index.h"

// --- The largest single allocation while tracking, to prove a hostile
// header cannot make the reader allocate what the file does not hold.
namespace {
std::atomic<bool> g_tracking{false};
std::atomic<size_t> g_largest_allocation{0};
}  // namespace

// noinline: GCC would otherwise see free() on a pointer from operator new.
__attribute__((noinline)) void* operator new(size_t n) {
  if (g_tracking.load(std::memory_order_relaxed)) {
    size_t seen = g_largest_allocation.load(std::memory_order_relaxed);
    while (n > seen && !g_largest_allocation.compare_exchange_weak(seen, n)) {
    }
  }
  if (void* p = std::malloc(n == 0 ? 1 : n)) return p;
  throw std::bad_alloc();
}
__attribute__((noinline)) void operator delete(void* p) noexcept { std::free(p); }
__attribute__((noinline)) void operator delete(void* p, size_t) noexcept { std::free(p); }

namespace relight {
namespace {

using namespace bake_test;  // NOLINT: test helpers

void WriteFileBytes(const std::string& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

class BakeIoTest : public BakeFileTest {
 protected:
  // Parses bytes that must be rejected as corrupt; `out` must stay untouched.
  std::string ExpectCorrupt(const Bytes& bytes, const std::string& part,
                            size_t max_allocation = 0) {
    Bake out;
    out.scene_name = "untouched";
    g_largest_allocation = 0;
    g_tracking = max_allocation != 0;
    Status st = ParseBake(bytes.data(), bytes.size(), &out);
    g_tracking = false;
    EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
    EXPECT_TRUE(Contains(st.message(), part)) << "'" << st.message() << "' lacks '" << part << "'";
    EXPECT_EQ(out.scene_name, "untouched");
    EXPECT_TRUE(out.luminaires.empty());
    if (max_allocation != 0) {
      EXPECT_LE(g_largest_allocation.load(), max_allocation);
    }
    return st.message();
  }
};

// Section order: META, MESH, GRID per grid, LUMI per luminaire, then per
// luminaire per receiver set DIRT (exact direct only) and BASE, then HIER and
// LINK (the test bake has a hierarchy).
TEST_F(BakeIoTest, RoundTripEqualsFieldByFieldInDocumentedSectionOrder) {
  Bake read;
  const Status st = ReadBake(Path("good.rlb"), &read);
  ASSERT_TRUE(st.ok()) << st.ToString();
  ExpectBakesEqual(bake_, read);

  Bake parsed;
  ASSERT_TRUE(ParseBake(file_.data(), file_.size(), &parsed).ok());
  ExpectBakesEqual(bake_, parsed);

  const std::vector<std::string> expected = {"META", "MESH", "GRID", "GRID", "LUMI",
                                             "LUMI", "DIRT", "BASE", "DIRT", "BASE",
                                             "DIRT", "BASE", "BASE", "BASE", "BASE",
                                             "HIER", "LINK"};
  const Container c = Split(file_);
  ASSERT_EQ(c.sections.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(c.sections[i].tag, Tag(expected[i].c_str())) << i;
  }
  EXPECT_EQ(GetLe<uint64_t>(&file_[16]), file_.size());
  // Re-encoding the sections with the test's own encoder gives the same bytes.
  Container again = c;
  Relayout(&again);
  EXPECT_EQ(Join(again), file_);
}

TEST_F(BakeIoTest, OverwriteReplacesTheFileAndLeavesNoTemporary) {
  const Bake other = MakeBake(8);
  ASSERT_TRUE(WriteBake(other, Path("good.rlb")).ok());
  Bake read;
  ASSERT_TRUE(ReadBake(Path("good.rlb"), &read).ok());
  ExpectBakesEqual(other, read);
  EXPECT_EQ(FileCount(), 1u);
}

TEST_F(BakeIoTest, TruncationAtEveryOffsetIsCorrupt) {
  for (size_t n = 0; n < file_.size(); ++n) {
    SCOPED_TRACE("truncated to " + std::to_string(n) + " bytes");
    const Bytes cut(file_.begin(), file_.begin() + static_cast<ptrdiff_t>(n));
    ExpectCorrupt(cut, "bake (in memory): ");
    if (HasFailure()) break;
  }
  // Through the file path too, at 0, inside the header, inside the TOC and
  // inside each section; the message names the file.
  std::vector<size_t> cuts = {0, 5, 20, kHeaderBytes + 10};
  for (const Section& s : Split(file_).sections) {
    cuts.push_back(static_cast<size_t>(s.offset + s.stored / 2));
  }
  for (size_t n : cuts) {
    const std::string path = Path("cut.rlb");
    WriteFileBytes(path, Bytes(file_.begin(), file_.begin() + static_cast<ptrdiff_t>(n)));
    Bake out;
    const Status st = ReadBake(path, &out);
    EXPECT_EQ(st.code(), StatusCode::kCorrupt) << n;
    EXPECT_TRUE(Contains(st.message(), "bake '" + path + "': ")) << st.message();
  }
}

TEST_F(BakeIoTest, SingleBitFlipsAreRejected) {
  const size_t toc_end = kHeaderBytes + kTocEntryBytes * Split(file_).sections.size();
  std::vector<std::pair<size_t, int>> flips;
  for (size_t i = 0; i < toc_end; ++i) {
    for (int bit = 0; bit < 8; ++bit) flips.push_back({i, bit});
  }
  const size_t payload_samples = 600;
  for (size_t k = 0; k < payload_samples; ++k) {
    const size_t at = toc_end + k * (file_.size() - toc_end) / payload_samples;
    flips.push_back({at, static_cast<int>(k % 8)});
  }
  for (const auto& [at, bit] : flips) {
    Bytes bad = file_;
    bad[at] = static_cast<uint8_t>(bad[at] ^ (1u << bit));
    Bake out;
    const Status st = ParseBake(bad.data(), bad.size(), &out);
    const bool in_version = at >= 8 && at < 12;  // a flipped version may read as a newer one
    if (in_version && st.code() == StatusCode::kUnsupported) continue;
    EXPECT_EQ(st.code(), StatusCode::kCorrupt) << "byte " << at << " bit " << bit;
    EXPECT_TRUE(out.luminaires.empty() && out.mesh.positions.empty());
    // Magic, version and section count are checked before the header crc;
    // every other byte is covered by the header crc or a section crc.
    if (at >= 16) {
      EXPECT_TRUE(Contains(st.message(), "crc mismatch")) << st.message();
    }
    if (HasFailure()) break;
  }
  std::printf("bit flips: %zu tried, all rejected\n", flips.size());
}

// ReadBake reads the file section by section (never the whole file at
// once): it must judge every damaged file as ParseBake judges the same bytes
// in memory, word for word apart from the name.
TEST_F(BakeIoTest, TheFileReaderAgreesWithTheMemoryReaderOnDamagedFiles) {
  std::vector<size_t> flips = {0, 9, 13, 17, kHeaderBytes + 3};
  for (const Section& s : Split(file_).sections) {
    flips.push_back(static_cast<size_t>(s.offset));
    flips.push_back(static_cast<size_t>(s.offset + s.stored - 1));
  }
  const std::string path = Path("flip.rlb");
  for (const size_t at : flips) {
    Bytes bad = file_;
    bad[at] = static_cast<uint8_t>(bad[at] ^ 0x10);
    WriteFileBytes(path, bad);
    Bake from_memory, from_file;
    const Status memory = ParseBake(bad.data(), bad.size(), &from_memory);
    const Status file = ReadBake(path, &from_file);
    EXPECT_FALSE(file.ok()) << "byte " << at;
    EXPECT_EQ(file.code(), memory.code()) << "byte " << at;
    std::string expected = memory.message();
    const std::string in_memory = "(in memory)";
    const size_t name = expected.find(in_memory);
    ASSERT_NE(name, std::string::npos) << expected;
    expected.replace(name, in_memory.size(), "'" + path + "'");
    EXPECT_EQ(file.message(), expected) << "byte " << at;
    EXPECT_TRUE(from_file.luminaires.empty() && from_file.mesh.positions.empty());
  }
}

// ReadBakeOptions::grids = false: the bake as if it had no grid, the rest
// as a full read gives it; the grids' sections are skipped unread (a damaged
// one goes unseen) but their sizes still checked.
TEST_F(BakeIoTest, ReadingWithoutGridsSkipsTheirSectionsAndKeepsTheRest) {
  ReadBakeOptions no_grids;
  no_grids.grids = false;
  Bake full, surfaces;
  ASSERT_TRUE(ReadBake(Path("good.rlb"), &full).ok());
  Status st = ReadBake(Path("good.rlb"), no_grids, &surfaces);
  ASSERT_TRUE(st.ok()) << st.ToString();
  ASSERT_FALSE(full.grids.empty());
  EXPECT_TRUE(surfaces.grids.empty());
  EXPECT_TRUE(surfaces.mesh.positions == full.mesh.positions && surfaces.mesh.triangles == full.mesh.triangles);
  ASSERT_EQ(surfaces.luminaires.size(), full.luminaires.size());
  for (size_t l = 0; l < full.luminaires.size(); ++l) {
    ASSERT_EQ(surfaces.luminaires[l].receivers.size(), 1u);
    EXPECT_TRUE(surfaces.luminaires[l].receivers[0].basis == full.luminaires[l].receivers[0].basis) << l;
    EXPECT_TRUE(surfaces.luminaires[l].receivers[0].direction == full.luminaires[l].receivers[0].direction) << l;
  }
  st = ValidateBake(surfaces);
  EXPECT_TRUE(st.ok()) << st.ToString();

  // The first luminaire's first grid BASE (after its vertex DIRT and BASE and the grid's DIRT): its payload damaged.
  Container c = Split(file_);
  const size_t grid_base = 2 + 2 + 2 + 3;  // META MESH, 2 GRID, 2 LUMI, then DIRT BASE DIRT
  ASSERT_EQ(c.sections[grid_base].tag, Tag("BASE"));
  c.sections[grid_base].bytes.back() ^= 0x5A;
  WriteFileBytes(Path("grid_damaged.rlb"), Join(c));
  EXPECT_EQ(ReadBake(Path("grid_damaged.rlb"), &full).code(), StatusCode::kCorrupt);
  st = ReadBake(Path("grid_damaged.rlb"), no_grids, &surfaces);
  EXPECT_TRUE(st.ok()) << st.ToString();
  // Its raw size made wrong: refused either way, before anything is decompressed.
  c = Split(file_);
  c.sections[grid_base].raw += 2;
  WriteFileBytes(Path("grid_size.rlb"), Join(c));
  st = ReadBake(Path("grid_size.rlb"), no_grids, &surfaces);
  EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "set 1")) << st.message();
}

TEST_F(BakeIoTest, NewerVersionIsUnsupportedAndVersionZeroCorrupt) {
  Container c = Split(file_);
  EXPECT_EQ(c.version, 3u);  // with a hierarchy
  c.version = 9;
  Bake out;
  const Bytes newer = Join(c);
  Status st = ParseBake(newer.data(), newer.size(), &out);
  EXPECT_EQ(st.code(), StatusCode::kUnsupported) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "version 9")) << st.message();
  c.version = 0;
  ExpectCorrupt(Join(c), "version 0");
}

TEST_F(BakeIoTest, HostileHeaderFieldsAreRejectedWithoutBigAllocations) {
  constexpr size_t kSmall = 64 * 1024;
  Bytes bad = file_;
  PutLe<uint32_t>(&bad[12], 0xFFFFFFFFu);
  ExpectCorrupt(bad, "section count", kSmall);

  bad = file_;
  PutLe<uint64_t>(&bad[16], 0xFFFFFFFFFFFFull);  // file size; crc fixed below
  const size_t toc_bytes = kTocEntryBytes * Split(file_).sections.size();
  PutLe(&bad[24], Crc(&bad[kHeaderBytes], toc_bytes, Crc(bad.data(), 24)));
  ExpectCorrupt(bad, "the header says", kSmall);

  Container c = Split(file_);
  c.sections[2].offset -= 4;
  ExpectCorrupt(Join(c), "overlaps", kSmall);

  c = Split(file_);
  c.sections[3].offset += 4;
  ExpectCorrupt(Join(c), "gap", kSmall);

  c = Split(file_);
  c.sections.back().offset = file_.size() + 100;
  ExpectCorrupt(Join(c), "past the end", kSmall);

  c = Split(file_);
  c.sections[5].offset = ~uint64_t{0} - 7;  // offset + size would overflow
  ExpectCorrupt(Join(c), "past the end", kSmall);

  c = Split(file_);
  c.sections[5].stored = ~uint64_t{0};
  ExpectCorrupt(Join(c), "runs past the end", kSmall);

  c = Split(file_);
  c.sections[1].flags |= 4;
  ExpectCorrupt(Join(c), "unknown flags", kSmall);

  c = Split(file_);
  std::swap(c.sections[0], c.sections[1]);
  Relayout(&c);
  ExpectCorrupt(Join(c), "is MESH, expected section META", kSmall);

  c = Split(file_);
  c.sections.pop_back();
  Relayout(&c);
  ExpectCorrupt(Join(c), "sections, the counts need", kSmall);

  c = Split(file_);
  c.sections.back().bytes.push_back(0);
  bad = Join(c);  // TOC unchanged, one trailing byte
  ExpectCorrupt(bad, "after the last section", kSmall);
}

TEST_F(BakeIoTest, RawSizeLiesAreRejectedBeforeDecompressing) {
  constexpr size_t kSmall = 64 * 1024;
  // META claims 2^26 vertices (the limit) and MESH the matching 1.6 GB of
  // raw bytes, but only a few compressed bytes back them.
  Container c = Split(file_);
  Bytes meta = Payload(c.sections[0]);
  const size_t counts_at = 4 + bake_.scene_name.size() + 4 + 28;
  PutLe<uint32_t>(&meta[counts_at], 1u << 26);
  SetPayload(&c.sections[0], meta, false);
  c.sections[1].raw = 24ull * (1u << 26) + 16 * 8 + (4 + 5) + (4 + 10) + (4 + 6);
  c.sections[1].flags = 1;
  Relayout(&c);
  ExpectCorrupt(Join(c), "cannot come from", kSmall);

  // A DIRT section whose raw size is not what the counts need.
  c = Split(file_);
  SetPayload(&c.sections[6], Payload(c.sections[6]), true);
  c.sections[6].raw += 10;
  Relayout(&c);
  ExpectCorrupt(Join(c), "section DIRT[lum 0 'spot', set 0]: raw size", kSmall);

  // MESH raw size within the slack the names allow, but not the frame's.
  c = Split(file_);
  ASSERT_EQ(c.sections[1].flags, 1u);
  c.sections[1].raw += 1;
  Relayout(&c);
  ExpectCorrupt(Join(c), "section MESH: zstd frame content size", kSmall);

  // LINK claims the bytes of more than 2^28 links, backed by just enough
  // stored bytes for zstd's expansion bound: the link limit refuses it.
  c = Split(file_);
  Section& link = c.sections.back();
  ASSERT_EQ(link.tag, Tag("LINK"));
  link.raw = 4 + 32 * (uint64_t{1} << 28) + 32;
  link.flags = 1;
  link.bytes.assign(static_cast<size_t>(link.raw / 65536 + 1), 0);
  Relayout(&c);
  ExpectCorrupt(Join(c), "section LINK: raw size 8589934628 is outside [4, 8589934596]", kSmall);

  // Uncompressed, the raw size must equal the stored size.
  c = Split(file_);
  SetPayload(&c.sections[4], Payload(c.sections[4]), false);
  c.sections[4].raw += 8;
  Relayout(&c);
  ExpectCorrupt(Join(c), "stored uncompressed, but raw size", kSmall);
}

TEST_F(BakeIoTest, HostileCountsAndFieldsInPayloadsAreRejected) {
  constexpr size_t kSmall = 64 * 1024;
  const size_t counts_at = 4 + bake_.scene_name.size() + 4 + 28;  // META: V, T, S, G, L
  const std::pair<size_t, const char*> meta_counts[] = {{0, "vertex count"},
                                                        {4, "triangle count"},
                                                        {8, "surface count"},
                                                        {12, "grid count"},
                                                        {16, "luminaire count"}};
  for (const auto& count : meta_counts) {
    const size_t off = count.first;  // a named copy: C++17 lambdas cannot capture a structured binding
    const char* what = count.second;
    for (bool compress : {false, true}) {
      ExpectCorrupt(
          EditPayload(
              file_, 0, [&](Bytes* p) { PutLe<uint32_t>(&(*p)[counts_at + off], 0xFFFFFFF0u); },
              compress),
          std::string("section META: ") + what, kSmall);
    }
  }
  ExpectCorrupt(EditPayload(file_, 0, [&](Bytes* p) { PutLe<int32_t>(&(*p)[4 + 9 + 4 + 24], 0); }),
                "fov_y");
  ExpectCorrupt(EditPayload(file_, 0, [&](Bytes* p) { p->push_back(0); }), "unused bytes");

  // LUMI[1] 'wash': name, position, then mounting, mode, degree, use_sigma.
  const size_t lumi = 5, fields = 4 + 4 + 12;
  ExpectCorrupt(EditPayload(file_, lumi, [&](Bytes* p) { (*p)[fields] = 7; }),
                "LUMI[1]: mounting 7");
  ExpectCorrupt(EditPayload(file_, lumi, [&](Bytes* p) { (*p)[fields + 1] = 3; }), "direct mode 3");
  ExpectCorrupt(EditPayload(file_, lumi, [&](Bytes* p) { (*p)[fields + 2] = 17; }), "SH degree 17");
  ExpectCorrupt(EditPayload(file_, lumi, [&](Bytes* p) { (*p)[fields + 3] = 2; }), "use_sigma 2");
  ExpectCorrupt(EditPayload(file_, lumi, [&](Bytes* p) { PutLe<int16_t>(&(*p)[fields + 12], -5); }),
                "default dimmer -5");
  ExpectCorrupt(
      EditPayload(file_, lumi, [&](Bytes* p) { PutLe<uint32_t>(&(*p)[fields + 20], 0x7FFFFFFFu); }),
      "LID has 2147483647 samples", kSmall);
  ExpectCorrupt(EditPayload(file_, lumi, [&](Bytes* p) { PutLe<int64_t>(&(*p)[fields + 24], -1); }),
                "LID sample 0");
  ExpectCorrupt(EditPayload(file_, lumi, [&](Bytes* p) { (*p)[5] = '\n'; }), "control character");
  ExpectCorrupt(EditPayload(file_, lumi, [&](Bytes* p) { std::memcpy(&(*p)[4], "spot", 4); }),
                "duplicate");
  ExpectCorrupt(EditPayload(file_, lumi, [&](Bytes* p) { PutLe<uint32_t>(&(*p)[0], 300); }),
                "length 300 exceeds 255");

  // MESH: a triangle index past the vertices, a surface index past the names.
  const size_t v = bake_.mesh.vertex_count(), t = bake_.mesh.triangle_count();
  ExpectCorrupt(EditPayload(file_, 1,
                            [&](Bytes* p) {
                              auto tri = DecodePlanar<uint32_t>(*p, 24 * v, 3 * t, 3);
                              tri[7] = static_cast<uint32_t>(v);
                              EncodePlanar(tri, 3, p, 24 * v);
                            }),
                "triangle 2: vertex index 11 >= vertex count 11");
  ExpectCorrupt(EditPayload(file_, 1,
                            [&](Bytes* p) {
                              auto surf = DecodePlanar<uint32_t>(*p, 24 * v + 12 * t, t, 1);
                              surf[3] = 3;
                              EncodePlanar(surf, 1, p, 24 * v + 12 * t);
                            }),
                "triangle 3: surface index 3 >= surface count 3");
  // GRID[0] 'desk': a normal that is not a unit vector.
  ExpectCorrupt(EditPayload(file_, 2,
                            [&](Bytes* p) {
                              const size_t at = 4 + 4 + 8 + 12 * 12;
                              auto n = DecodePlanar<int16_t>(*p, at, 36, 3);
                              n[6] = 16384, n[7] = 16384, n[8] = 0;  // length sqrt(2)
                              EncodePlanar(n, 3, p, at);
                            }),
                "GRID[0]: point normal 2");
  ExpectCorrupt(EditPayload(file_, 2, [&](Bytes* p) { PutLe<uint32_t>(&(*p)[8], 5); }),
                "columns x rows = 5 x 3");
  // DIRT[spot, set 0]: a direction that is not a unit vector; a bad scale.
  ExpectCorrupt(EditPayload(file_, 6,
                            [&](Bytes* p) {
                              auto d = DecodePlanar<int16_t>(*p, 8, 3 * v, 3);
                              d[0] = 0, d[1] = 0, d[2] = 100;
                              EncodePlanar(d, 3, p, 8);
                            }),
                "section DIRT[lum 0 'spot', set 0]: receiver direction 0");
  ExpectCorrupt(EditPayload(file_, 6, [&](Bytes* p) { PutLe<int32_t>(&(*p)[0], 5); }),
                "geometry_scale: mantissa 5");
  // BASE[wash, set 2]: mantissa outside [2^29, 2^30); a zero scale over non-zero values.
  ExpectCorrupt(EditPayload(file_, 14, [&](Bytes* p) { PutLe<int32_t>(&(*p)[8 * 4], 1 << 30); }),
                "section BASE[lum 1 'wash', set 2]: basis_scale[term 1][channel 1]: mantissa");
  ExpectCorrupt(EditPayload(file_, 14, [&](Bytes* p) { PutLe<int32_t>(&(*p)[8 * 4 + 4], 500); }),
                "exponent 500");
  ExpectCorrupt(EditPayload(
                    file_, 14, [&](Bytes* p) { PutLe<uint64_t>(&(*p)[0], 0); }, true),
                "term 0 channel 0: zero scale but receiver");
}

// LUMI of format version 2 ends with the orientation, the console ranges, the
// (C, gamma) table and its SH coefficients (docs/bake-format.md).
TEST_F(BakeIoTest, HostileLuminaireTailsAreRejected) {
  constexpr size_t kSmall = 64 * 1024;
  // LUMI[0] 'spot': 181 LID samples, then the tail; 4 planes, 7 gammas, degree 2.
  const size_t lumi = 4, fields = 4 + 4 + 12, tail = fields + 24 + 8 * 181;
  const size_t c_at = tail + 24, g_at = c_at + 4 * 4, table_at = g_at + 4 * 7;
  const size_t sh_count_at = table_at + 8 * 4 * 7, sh_at = sh_count_at + 4;
  ASSERT_EQ(Payload(Split(file_).sections[lumi]).size(), sh_at + 8 * 9);
  const auto edit = [&](const std::function<void(Bytes*)>& f) { return EditPayload(file_, lumi, f); };
  ExpectCorrupt(edit([&](Bytes* p) { (*p)[fields] = 3; }),
                "LUMI[0]: mounting 3 is not 0 (hanging), 1 (standing) or 2 (wall)");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<int32_t>(&(*p)[tail], 361 << 16); }), "yaw");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<int32_t>(&(*p)[tail + 4], -(400 << 16)); }), "roll");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<int32_t>(&(*p)[tail + 8], 0); }), "pan range 0");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<int32_t>(&(*p)[tail + 12], 400 << 16); }), "tilt range");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<uint32_t>(&(*p)[tail + 16], 0x7FFFFFFFu); }),
                "LID table of 2147483647 planes", kSmall);
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<uint32_t>(&(*p)[tail + 20], 0); }), "LID table of 4 planes x 0");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<int32_t>(&(*p)[c_at + 4], 0); }),
                "LID C angle 1 does not increase");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<int32_t>(&(*p)[c_at + 12], 359 << 16); }),
                "from 0 to 360");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<int32_t>(&(*p)[g_at + 24], 200 << 16); }),
                "LID gamma angle 6");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<int64_t>(&(*p)[table_at], -1); }), "LID table value 0");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<int64_t>(&(*p)[table_at + 8 * 21], 12345); }),
                "plane at C 360 differs from C 0 at gamma 0");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<uint32_t>(&(*p)[sh_count_at], 1000); }),
                "LID has 1000 SH coefficients", kSmall);
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<uint32_t>(&(*p)[sh_count_at], 4); }), "unused bytes");
  ExpectCorrupt(edit([&](Bytes* p) { PutLe<int64_t>(&(*p)[sh_at], INT64_MAX); }),
                "LID SH coefficient 0");
  ExpectCorrupt(edit([&](Bytes* p) { p->resize(p->size() - 8); }), "LUMI[0]");
}

// Format version 1 (no LUMI tail, no hierarchy) still reads, with the defaults of version 2.
TEST_F(BakeIoTest, Version1FilesStillRead) {
  Container c = Split(file_);
  c.version = 1;
  c.sections.resize(c.sections.size() - 2);  // HIER, LINK
  Bake expected = bake_;
  expected.hierarchy.reset();
  for (size_t l = 0; l < 2; ++l) {
    Section& lumi = c.sections[4 + l];
    Bytes raw = Payload(lumi);
    const size_t samples = expected.luminaires[l].lid.candela.size();
    raw.resize(4 + expected.luminaires[l].name.size() + 36 + 8 * samples);
    SetPayload(&lumi, raw, l == 1);
    BakeLuminaire& lum = expected.luminaires[l];
    lum.lid.c_deg.clear();
    lum.lid.gamma_deg.clear();
    lum.lid.table.clear();
    lum.lid.sh.clear();
    lum.yaw = lum.roll = 0;
    lum.pan_range = 540 << 16;
    lum.tilt_range = 270 << 16;
  }
  Relayout(&c);
  const Bytes v1 = Join(c);
  Bake out;
  const Status st = ParseBake(v1.data(), v1.size(), &out);
  ASSERT_TRUE(st.ok()) << st.ToString();
  ExpectBakesEqual(expected, out);
  // A version 2 reader insists on the tail.
  c.version = 2;
  ExpectCorrupt(Join(c), "LUMI[0]");
}

// Random damage behind valid crcs reaches the semantic checks: the reader
// must reject or accept without crashing, and whatever it accepts the writer
// must accept too (both sides share one set of rules).
TEST_F(BakeIoTest, DamagedPayloadsWithValidCrcsAreRejectedOrRoundTrip) {
  std::vector<size_t> sections(Split(file_).sections.size());
  for (size_t i = 0; i < sections.size(); ++i) sections[i] = i;
  const auto [accepted, rejected] = DamagePayloads(file_, sections, 1000, 11, Path("again.rlb"));
  std::printf("damaged payloads: %zu accepted (random values still in range), %zu rejected\n",
              accepted, rejected);
  EXPECT_GT(rejected, 0u);
}

TEST_F(BakeIoTest, SectionCrcMismatchNamesTheSection) {
  Container c = Split(file_);
  c.sections[9].crc ^= 1;  // BASE[lum 0 'spot', set 1]
  const std::string message =
      ExpectCorrupt(Join(c), "section BASE[lum 0 'spot', set 1]: crc mismatch");
  EXPECT_EQ(message.rfind("bake (in memory): ", 0), 0u) << message;
}

TEST_F(BakeIoTest, WriteRejectsInconsistentBakesAndKeepsTheOldFile) {
  ExpectWriteRejects({
      {"mesh: normals has 30 values", [](Bake* b) { b->mesh.normals.resize(30); }},
      {"mesh: albedo has 34 values", [](Bake* b) { b->mesh.albedo.push_back(1); }},
      {"mesh: triangle 0: vertex index 11", [](Bake* b) { b->mesh.triangles[0] = 11; }},
      {"mesh: triangle_surface has 7 values", [](Bake* b) { b->mesh.triangle_surface.pop_back(); }},
      {"mesh: triangle 4: surface index 9", [](Bake* b) { b->mesh.triangle_surface[4] = 9; }},
      {"mesh: vertex normal 0",
       [](Bake* b) { b->mesh.normals[0] = 0, b->mesh.normals[1] = 0, b->mesh.normals[2] = 0; }},
      {"grid 1: columns x rows = 2 x 2, but 5 points",
       [](Bake* b) { b->grids[1].columns = b->grids[1].rows = 2; }},
      {"grids: grid 1 has the same name 'desk'", [](Bake* b) { b->grids[1].name = "desk"; }},
      {"luminaire 0 'spot': has 2 receiver sets, expected 1 + 2 grids = 3",
       [](Bake* b) { b->luminaires[0].receivers.pop_back(); }},
      {"luminaire 0 'spot', receiver set 1 (grid 0 'desk'): direction has 33 values, expected 3 x "
       "receivers = 36",
       [](Bake* b) { b->luminaires[0].receivers[1].direction.resize(33); }},
      {"luminaire 0 'spot', receiver set 0 (vertices): geometry has 10 values",
       [](Bake* b) { b->luminaires[0].receivers[0].geometry.pop_back(); }},
      {"luminaire 1 'wash', receiver set 0 (vertices): direction and geometry must be empty",
       [](Bake* b) { b->luminaires[1].receivers[0].geometry = {1}; }},
      {"luminaire 1 'wash', receiver set 2 (grid 1 'path'): basis has 239 values, expected 3 x "
       "terms x receivers = 240",
       [](Bake* b) { b->luminaires[1].receivers[2].basis.pop_back(); }},
      {"basis_scale has 27 values, expected 3 x terms = 48",
       [](Bake* b) { b->luminaires[1].receivers[0].basis_scale.resize(27); }},
      {"basis_scale[term 2][channel 0]: mantissa 12 is outside",
       [](Bake* b) { b->luminaires[0].receivers[0].basis_scale[6].mantissa = 12; }},
      {"luminaire 0: SH degree 23 exceeds the maximum 22",
       [](Bake* b) { b->luminaires[0].sh_degree = 23; }},
      {"luminaire 1: LID has 2 samples", [](Bake* b) { b->luminaires[1].lid.candela.resize(2); }},
      {"luminaire 1: name is 300 bytes", [](Bake* b) { b->luminaires[1].name.assign(300, 'x'); }},
      {"luminaire 1: name is not UTF-8",
       [](Bake* b) {
         b->luminaires[1].name =
             "w\xFF"
             "sh";
       }},
      {"luminaires: luminaire 1 has the same name 'spot'",
       [](Bake* b) { b->luminaires[1].name = "spot"; }},
      {"luminaire 0: mounting 9",
       [](Bake* b) { b->luminaires[0].mounting = static_cast<Mounting>(9); }},
      {"luminaire 0: default colour -1", [](Bake* b) { b->luminaires[0].default_rgb[2] = -1; }},
      {"luminaire 0: LID table has 27 values, expected planes x gammas = 28",
       [](Bake* b) { b->luminaires[0].lid.table.pop_back(); }},
      {"luminaire 0: LID SH coefficients has 4 values, expected (N+1)^2 = 9",
       [](Bake* b) { b->luminaires[0].lid.sh.resize(4); }},
      {"luminaire 1: an axisymmetric LID (no C planes) has no gammas",
       [](Bake* b) { b->luminaires[1].lid.gamma_deg = {0, 1}; }},
      {"luminaire 1: pan range 0", [](Bake* b) { b->luminaires[1].pan_range = 0; }},
      {"scene: white luminance 0", [](Bake* b) { b->white_luminance = 0; }},
      {"counts: grid count 65 exceeds the limit 64",
       [](Bake* b) {
         for (int g = 0; g < 63; ++g) {
           BakeGrid grid;
           grid.name = "g" + std::to_string(g);
           b->grids.push_back(grid);
         }
       }},
  });
}

TEST_F(BakeIoTest, FailedWritesLeaveTheExistingFileUntouched) {
  const std::string path = Path("good.rlb");
  // The temporary's name is taken (by a directory): nothing can be written.
  const std::string tmp = path + ".tmp." + std::to_string(::getpid());
  ASSERT_EQ(::mkdir(tmp.c_str(), 0755), 0);
  Status st = WriteBake(MakeBake(9), path);
  EXPECT_EQ(st.code(), StatusCode::kIoError) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "cannot create")) << st.message();
  EXPECT_EQ(ReadFileBytes(path), file_);
  ASSERT_EQ(::rmdir(tmp.c_str()), 0);

  // The target is a directory: the rename fails, the temporary is removed.
  const std::string sub = Path("sub");
  ASSERT_EQ(::mkdir(sub.c_str(), 0755), 0);
  st = WriteBake(bake_, sub);
  EXPECT_EQ(st.code(), StatusCode::kIoError) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "rename failed")) << st.message();
  EXPECT_TRUE(std::filesystem::is_directory(sub));
  EXPECT_EQ(FileCount(), 2u);

  // The directory does not exist.
  st = WriteBake(bake_, Path("missing/x.rlb"));
  EXPECT_EQ(st.code(), StatusCode::kIoError) << st.ToString();

  // The disk fills up halfway (a file size limit): the old file survives.
  struct rlimit old_limit;
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old_limit), 0);
  struct rlimit small = old_limit;
  small.rlim_cur = 1024;
  ASSERT_LT(small.rlim_cur, file_.size());
  void (*old_handler)(int) = ::signal(SIGXFSZ, SIG_IGN);
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  st = WriteBake(MakeBake(10), path);
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old_limit), 0);
  ::signal(SIGXFSZ, old_handler);
  EXPECT_EQ(st.code(), StatusCode::kIoError) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "write failed")) << st.message();
  EXPECT_EQ(ReadFileBytes(path), file_);
  EXPECT_EQ(FileCount(), 2u);

  // A directory without write permission (root writes anyway: skip then).
  if (::geteuid() != 0) {
    ASSERT_EQ(::chmod(dir_.c_str(), 0555), 0);
    st = WriteBake(MakeBake(11), path);
    ::chmod(dir_.c_str(), 0755);
    EXPECT_EQ(st.code(), StatusCode::kIoError) << st.ToString();
    EXPECT_EQ(ReadFileBytes(path), file_);
  }
}

TEST_F(BakeIoTest, ReadingWhatIsNotABakeFile) {
  Bake out;
  Status st = ReadBake(Path("missing.rlb"), &out);
  EXPECT_EQ(st.code(), StatusCode::kNotFound) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), Path("missing.rlb"))) << st.message();
  st = ReadBake(dir_, &out);
  EXPECT_EQ(st.code(), StatusCode::kIoError) << st.ToString();
  const std::string text = Path("text.rlb");
  WriteFileBytes(text, Bytes{'h', 'e', 'l', 'l', 'o', '\n'});
  st = ReadBake(text, &out);
  EXPECT_EQ(st.code(), StatusCode::kCorrupt);
  EXPECT_EQ(st.message(), "bake '" + text + "': header: bad magic, not a relight bake");
}

// A sizable smooth basis (a 128 x 96 vertex floor lit by a degree-4
// luminaire, quantised per term and channel like the baker does, plus
// Gaussian noise of `noise_lsb`), for the compression figures in
// docs/bake-format.md. `shuffled` numbers the vertices in random order, the
// worst case for the delta step.
struct CompressionFigures {
  uint64_t raw = 0, stored = 0;
  size_t plain_zstd = 0;
};

CompressionFigures MeasureSmoothBasis(const std::string& path, double noise_lsb, bool shuffled) {
  const int kW = 128, kH = 96, kV = kW * kH, kDegree = 4, kTerms = ShTermCount(kDegree);
  std::mt19937 rng(3);
  std::vector<int> order(kV);  // grid cell of vertex v
  for (int v = 0; v < kV; ++v) order[v] = v;
  if (shuffled) std::shuffle(order.begin(), order.end(), rng);
  std::vector<uint32_t> vertex_of(kV);
  for (int v = 0; v < kV; ++v) vertex_of[order[v]] = static_cast<uint32_t>(v);
  Bake b;
  b.scene_name = "floor";
  for (int v = 0; v < kV; ++v) {
    b.mesh.positions.insert(b.mesh.positions.end(),
                            {(order[v] % kW) << 14, (order[v] / kW) << 14, 0});
    b.mesh.normals.insert(b.mesh.normals.end(), {0, 0, 16384});
    b.mesh.albedo.insert(b.mesh.albedo.end(), {40000, 36000, 30000});
  }
  for (int y = 0; y + 1 < kH; ++y) {
    for (int x = 0; x + 1 < kW; ++x) {
      const int i = y * kW + x;
      for (int corner : {i, i + 1, i + kW, i + 1, i + kW + 1, i + kW}) {
        b.mesh.triangles.push_back(vertex_of[corner]);
      }
      b.mesh.triangle_surface.insert(b.mesh.triangle_surface.end(), {0, 0});
    }
  }
  b.mesh.surface_names = {"floor"};
  BakeLuminaire lum = MakeLuminaire(&rng, "key", DirectMode::kAllInSh, kDegree, 721);
  BakeLightReceivers rec;
  rec.basis.resize(size_t{3} * kTerms * kV);
  std::normal_distribution<double> noise(0, 1);
  for (int t = 0; t < kTerms; ++t) {
    for (int c = 0; c < 3; ++c) {
      rec.basis_scale.push_back(QuantScale{(1 << 29) + t * 1000 + c, -20 - t});
      for (int v = 0; v < kV; ++v) {
        const double x = (order[v] % kW) / double(kW) - 0.5, y = (order[v] / kW) / double(kH) - 0.4;
        const double f = std::cos(3.0 * x * (t % 5 + 1) + t) * std::cos(2.0 * y * (t / 5 + 1)) *
                         std::exp(-3.0 * (x * x + y * y)) * (0.7 + 0.1 * c);
        const double q = std::clamp(f * 32767.0 + noise_lsb * noise(rng), -32767.0, 32767.0);
        rec.basis[(size_t(t) * kV + v) * 3 + c] = static_cast<int16_t>(std::lround(q));
      }
    }
  }
  lum.receivers = {rec};
  b.luminaires = {lum};
  CompressionFigures f;
  const Status st = WriteBake(b, path);
  EXPECT_TRUE(st.ok()) << st.ToString();
  const Bytes file = ReadFileBytes(path);
  Bake read;
  EXPECT_TRUE(ParseBake(file.data(), file.size(), &read).ok());
  ExpectBakesEqual(b, read);

  // The same values as plain interleaved little-endian int16, zstd level 6.
  Bytes plain(rec.basis.size() * 2);
  for (size_t i = 0; i < rec.basis.size(); ++i) PutLe(&plain[2 * i], rec.basis[i]);
  Bytes packed(ZSTD_compressBound(plain.size()));
  f.plain_zstd = ZSTD_compress(packed.data(), packed.size(), plain.data(), plain.size(), 6);
  const Container c = Split(file);
  const Section& base = c.sections.back();
  EXPECT_EQ(base.tag, Tag("BASE"));
  EXPECT_EQ(base.flags, 1u);
  f.raw = base.raw;
  f.stored = base.stored;
  std::printf(
      "smooth basis %d vertices x %d terms x 3, noise %.0f LSB, %s order: raw %llu B, "
      "plain zstd-6 %zu B (%.1f %%), bake BASE %llu B (%.1f %%); MESH %llu B -> %llu B\n",
      kV, kTerms, noise_lsb, shuffled ? "shuffled" : "raster",
      static_cast<unsigned long long>(f.raw), f.plain_zstd,
      100.0 * double(f.plain_zstd) / double(f.raw), static_cast<unsigned long long>(f.stored),
      100.0 * double(f.stored) / double(f.raw), static_cast<unsigned long long>(c.sections[1].raw),
      static_cast<unsigned long long>(c.sections[1].stored));
  return f;
}

TEST_F(BakeIoTest, SmoothBasisCompressionFigures) {
  for (const auto& [noise_lsb, shuffled] : {std::pair{0.0, false}, {3.0, false}, {3.0, true}}) {
    const CompressionFigures f = MeasureSmoothBasis(Path("smooth.rlb"), noise_lsb, shuffled);
    // The planar delta layout must not lose to plain zstd, in any vertex order.
    EXPECT_LT(f.stored, f.plain_zstd);
  }
}

}  // namespace
}  // namespace relight
