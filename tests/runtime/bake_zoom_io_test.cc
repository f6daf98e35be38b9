// A luminaire's zoom in the bake file (LUMI's version 4 tail, docs/bake-format.md):
// written only when a luminaire zooms (the lowest version that holds the
// bake), read back exactly, every rule broken once through WriteBake
// (kInvalidArgument) and through the reader (kCorrupt naming LUMI[1]), and
// older files still read without one.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "bake_file_edit.h"
#include "bake_test_bake.h"
#include "relight/bake/bake.h"

namespace relight {
namespace {

using namespace bake_test;  // NOLINT: test helpers

constexpr size_t kLumi1 = 5;  // META, MESH, GRID x 2, LUMI[0], then LUMI[1]
constexpr size_t kProfile = 17;

BakeZoom MakeZoom() {
  BakeZoom z;
  z.min_deg = 12 << 16;
  z.max_deg = 60 << 16;
  z.default_deg = 30 << 16;
  z.lumens = int64_t{1200} << 16;
  z.profile_end = (5 << 16) / 2;
  for (size_t k = 0; k < kProfile; ++k) {
    z.profile.push_back(static_cast<int32_t>((int64_t{1} << 30) * (kProfile - k) / kProfile));
  }
  return z;
}

class BakeZoomIoTest : public BakeFileTest {
 protected:
  void SetUp() override {
    BakeFileTest::SetUp();
    ASSERT_TRUE(bake_.luminaires[1].lid.axisymmetric());
    zoomed_ = bake_;
    zoomed_.luminaires[1].zoom = MakeZoom();
    ASSERT_TRUE(WriteBake(zoomed_, Path("zoom.rlb")).ok());
    zoom_file_ = ReadFileBytes(Path("zoom.rlb"));
  }

  // The zoom tail's first byte in LUMI[1]'s payload (its profile count).
  static size_t TailAt(const Bytes& payload) { return payload.size() - (4 + 24 + 4 * kProfile); }

  void ExpectCorrupt(const Bytes& bytes, const std::string& part) {
    Bake out;
    const Status st = ParseBake(bytes.data(), bytes.size(), &out);
    EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
    EXPECT_TRUE(Contains(st.message(), "section LUMI[1]")) << st.message();
    EXPECT_TRUE(Contains(st.message(), part)) << "'" << st.message() << "' lacks '" << part << "'";
    EXPECT_TRUE(out.luminaires.empty());
  }
  Bytes EditTail(const std::function<void(Bytes*, size_t)>& edit) {
    return EditPayload(zoom_file_, kLumi1, [&](Bytes* p) { edit(p, TailAt(*p)); });
  }

  Bake zoomed_;
  Bytes zoom_file_;
};

TEST_F(BakeZoomIoTest, AZoomMakesVersion4AndReadsBackExactly) {
  EXPECT_EQ(Split(file_).version, 3u);  // no zoom: as before
  EXPECT_EQ(Split(zoom_file_).version, 4u);
  Bake read;
  ASSERT_TRUE(ParseBake(zoom_file_.data(), zoom_file_.size(), &read).ok());
  ExpectBakesEqual(zoomed_, read);
  EXPECT_FALSE(read.luminaires[0].zoom.present());
  // Without a hierarchy too: the version says zoom, not hierarchy.
  Bake plain = zoomed_;
  plain.hierarchy.reset();
  ASSERT_TRUE(WriteBake(plain, Path("plain.rlb")).ok());
  const Bytes bytes = ReadFileBytes(Path("plain.rlb"));
  EXPECT_EQ(Split(bytes).version, 4u);
  ASSERT_TRUE(ParseBake(bytes.data(), bytes.size(), &read).ok());
  ExpectBakesEqual(plain, read);
}

TEST_F(BakeZoomIoTest, OlderVersionsHaveNoZoomTail) {
  // A version 3 reader reading the zoom file's LUMI would find bytes it does not know.
  // (every LUMI of a version 4 file has one, LUMI[0]'s just its count 0).
  Container c = Split(zoom_file_);
  c.version = 3;
  Bake out;
  const Bytes v3 = Join(c);
  Status st = ParseBake(v3.data(), v3.size(), &out);
  EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "section LUMI[0]: 4 unused bytes")) << st.message();
  // And a version 4 file without the tails is short.
  c = Split(file_);
  c.version = 4;
  const Bytes v4 = Join(c);
  st = ParseBake(v4.data(), v4.size(), &out);
  EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "section LUMI[0]")) << st.message();
}

TEST_F(BakeZoomIoTest, ReaderRejectsEveryBrokenRuleNamingTheSection) {
  const auto put32 = [](Bytes* p, size_t at, uint32_t v) { PutLe<uint32_t>(&(*p)[at], v); };
  ExpectCorrupt(EditTail([&](Bytes* p, size_t t) { put32(p, t, 1); }), "zoom profile has 1 samples");
  ExpectCorrupt(EditTail([&](Bytes* p, size_t t) { put32(p, t, 0x7FFFFFFF); }),
                "zoom profile has 2147483647 samples");
  ExpectCorrupt(EditTail([&](Bytes* p, size_t t) { put32(p, t, 4000); }), "too short for the zoom");
  ExpectCorrupt(EditTail([&](Bytes* p, size_t t) { put32(p, t, 0); }), "unused bytes");
  ExpectCorrupt(EditTail([&](Bytes* p, size_t t) { put32(p, t + 4, 0); }), "zoom range 0 ..");
  ExpectCorrupt(EditTail([&](Bytes* p, size_t t) { put32(p, t + 8, 180 << 16); }), "within (0, 180)");
  ExpectCorrupt(EditTail([&](Bytes* p, size_t t) { put32(p, t + 12, 61 << 16); }),
                "zoom default 3997696");
  ExpectCorrupt(EditTail([&](Bytes* p, size_t t) { PutLe<int64_t>(&(*p)[t + 16], -1); }),
                "zoom lumens -1");
  ExpectCorrupt(EditTail([&](Bytes* p, size_t t) { put32(p, t + 24, 1 << 16); }),
                "zoom profile end 65536");
  ExpectCorrupt(EditTail([&](Bytes* p, size_t t) { put32(p, t + 28, 1 << 29); }),
                "zoom profile sample 0");
  ExpectCorrupt(EditTail([&](Bytes* p, size_t t) { put32(p, t + 28 + 4 * 5, 1 << 30); }),
                "zoom profile sample 5");
  ExpectCorrupt(EditTail([&](Bytes* p, size_t) { p->pop_back(); }), "LUMI[1]");
}

TEST_F(BakeZoomIoTest, WriterRejectsEveryBrokenRuleAndKeepsTheOldFile) {
  bake_ = zoomed_;
  file_ = zoom_file_;
  ASSERT_TRUE(WriteBake(bake_, Path("good.rlb")).ok());
  std::filesystem::remove(Path("zoom.rlb"));  // the directory holds good.rlb alone
  using Z = BakeZoom;
  const auto zoom = [](const std::function<void(Z*)>& f) {
    return [f](Bake* b) { f(&b->luminaires[1].zoom); };
  };
  ExpectWriteRejects({
      {"zoom profile has 1 samples", zoom([](Z* z) { z->profile.resize(1); })},
      {"zoom range", zoom([](Z* z) { z->min_deg = 0; })},
      {"zoom range", zoom([](Z* z) { z->max_deg = 180 << 16; })},
      {"zoom range", zoom([](Z* z) { z->min_deg = z->max_deg + 1; })},
      {"zoom default", zoom([](Z* z) { z->default_deg = 11 << 16; })},
      {"zoom lumens", zoom([](Z* z) { z->lumens = (int64_t{1} << 48) + 1; })},
      {"zoom profile end", zoom([](Z* z) { z->profile_end = 65 << 16; })},
      {"zoom profile sample 0", zoom([](Z* z) { z->profile[0] = 5; })},
      {"zoom profile sample 3", zoom([](Z* z) { z->profile[3] = -1; })},
      {"without a zoom profile has no zoom angles", zoom([](Z* z) { z->profile.clear(); })},
      {"only an axisymmetric LID", [](Bake* b) { b->luminaires[0].zoom = MakeZoom(); }},
  });
}

}  // namespace
}  // namespace relight
