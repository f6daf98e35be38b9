// Links from the hierarchy to the grid points (section GLNK, format version
// 6): the round trip, every validation rule broken once through WriteBake
// (kInvalidArgument) and through the reader (kCorrupt, naming the section),
// the version and section-count rules, and random damage to the section.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "bake_file_edit.h"
#include "bake_test_bake.h"
#include "relight/bake/bake.h"

namespace relight {
namespace {

using namespace bake_test;  // NOLINT: test helpers

constexpr size_t kGlnk = 17;      // after HIER (15) and LINK (16) in MakeBake's file
constexpr uint32_t kPoints = 17;  // MakeBake's grids: 12 + 5 points

// Point p links to nodes {1, 2, 6} (p % 3 == 0), {0, 7} (1) or none (2):
// inner and leaf nodes, on several surfaces.
void AddGridLinks(BakeHierarchy* h) {
  h->grid_link_offsets = {0};
  for (uint32_t p = 0; p < kPoints; ++p) {
    std::vector<uint32_t> nodes;
    if (p % 3 == 0) nodes = {1, 2, 6};
    if (p % 3 == 1) nodes = {0, 7};
    for (uint32_t n : nodes) {
      h->grid_link_node.push_back(n);
      h->grid_link_f.push_back(0x10000000u * (1 + (p + n) % 5));  // 1/16 .. 5/16
    }
    h->grid_link_offsets.push_back(static_cast<uint32_t>(h->grid_link_node.size()));
  }
}

// GLNK payload: P, K, offsets[P + 1], node[K], f[K].
constexpr size_t kOffsetsAt = 8;
size_t NodesAt() { return kOffsetsAt + 4 * (kPoints + 1); }

class BakeGridLinksIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    bake_ = bake_test::MakeBake(7);
    AddGridLinks(&*bake_.hierarchy);
    links_ = bake_.hierarchy->grid_link_node.size();
    // One file per test and process: ctest -j runs this binary's tests at once.
    path_ = ::testing::TempDir() + "bake_grid_links_io_test_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" + std::to_string(getpid()) + ".rlb";
    ASSERT_TRUE(WriteBake(bake_, path_).ok());
    file_ = ReadFileBytes(path_);
  }
  void TearDown() override { std::remove(path_.c_str()); }

  void ExpectCorrupt(const Bytes& bytes, const std::string& part) {
    Bake out;
    const Status st = ParseBake(bytes.data(), bytes.size(), &out);
    EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
    EXPECT_TRUE(Contains(st.message(), part)) << "'" << st.message() << "' lacks '" << part << "'";
  }
  Bytes EditU32(size_t at, size_t n, const std::function<void(std::vector<uint32_t>*)>& edit) const {
    return EditPayload(file_, kGlnk, [&](Bytes* p) {
      std::vector<uint32_t> v = DecodePlanar<uint32_t>(*p, at, n, 1);
      edit(&v);
      EncodePlanar(v, 1, p, at);
    });
  }

  Bake bake_;
  size_t links_ = 0;
  std::string path_;
  Bytes file_;
};

TEST_F(BakeGridLinksIoTest, RoundTripsAsVersion6WithGlnkAfterLink) {
  const Container c = Split(file_);
  EXPECT_EQ(c.version, 6u);
  ASSERT_EQ(c.sections.size(), kGlnk + 1);
  EXPECT_EQ(c.sections[kGlnk - 1].tag, Tag("LINK"));
  EXPECT_EQ(c.sections[kGlnk].tag, Tag("GLNK"));
  Bake back;
  ASSERT_TRUE(ReadBake(path_, &back).ok());
  ExpectBakesEqual(bake_, back);
  EXPECT_TRUE(back.hierarchy->has_grid_links());
  // Without grid links the same bake stays version 3 (older readers read it).
  Bake plain = bake_test::MakeBake(7);
  ASSERT_TRUE(WriteBake(plain, path_).ok());
  EXPECT_EQ(Split(ReadFileBytes(path_)).version, 3u);
}

TEST_F(BakeGridLinksIoTest, VersionAndSectionCountRules) {
  Container c = Split(file_);
  c.version = 5;  // GLNK needs version 6
  ExpectCorrupt(Join(c), "18 sections, the counts need 15 (or 17 with HIER and LINK)");
  c = Split(file_);
  c.sections[kGlnk].tag = Tag("BASE");
  ExpectCorrupt(Join(c), "TOC entry 17: is BASE, expected section GLNK");
}

TEST_F(BakeGridLinksIoTest, ReaderNamesWhatIsWrong) {
  ExpectCorrupt(EditPayload(file_, kGlnk, [](Bytes* p) { PutLe<uint32_t>(p->data(), 16); }),
                "section GLNK: point count 16, the grids have 17");
  ExpectCorrupt(EditPayload(file_, kGlnk, [](Bytes* p) { PutLe<uint32_t>(p->data() + 4, 1000); }),
                "section GLNK: raw size");
  ExpectCorrupt(EditPayload(file_, kGlnk, [](Bytes* p) { PutLe<uint32_t>(p->data() + 4, 0xFFFFFFFFu); }),
                "exceed the limit");
  ExpectCorrupt(EditPayload(file_, kGlnk, [](Bytes* p) { p->resize(6); }), "section GLNK");
  ExpectCorrupt(EditPayload(file_, kGlnk, [](Bytes* p) { p->push_back(0); }), "section GLNK");
  ExpectCorrupt(EditU32(kOffsetsAt, kPoints + 1, [](auto* v) { (*v)[0] = 1; }),
                "grid link offsets run from 1");
  ExpectCorrupt(EditU32(kOffsetsAt, kPoints + 1, [](auto* v) { (*v)[3] = (*v)[2] - 1; }),
                "grid point 2: links [5, 4)");
  ExpectCorrupt(EditU32(NodesAt(), links_, [](auto* v) { (*v)[1] = 8; }),
                "grid point 0, link 1: node 8 >= node count 8");
  ExpectCorrupt(EditU32(NodesAt(), links_, [](auto* v) { (*v)[1] = 1; }),
                "grid point 0, link 1: node 1 does not come after 1");
  ExpectCorrupt(EditU32(NodesAt() + 4 * links_, links_, [](auto* v) { (*v)[0] = (*v)[1] = (*v)[2] = 0xFFFFFFFFu; }),
                "grid point 0: its link factors sum to more than 2");
}

TEST_F(BakeGridLinksIoTest, WriterRejectsTheSameRules) {
  const auto expect_invalid = [&](const std::function<void(BakeHierarchy*)>& spoil, const std::string& part) {
    Bake b = bake_;
    spoil(&*b.hierarchy);
    const Status st = WriteBake(b, path_ + ".bad");
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << st.ToString();
    EXPECT_TRUE(Contains(st.message(), "hierarchy grid links")) << st.message();
    EXPECT_TRUE(Contains(st.message(), part)) << "'" << st.message() << "' lacks '" << part << "'";
  };
  expect_invalid([](BakeHierarchy* h) { h->grid_link_offsets.pop_back(); }, "grid_link_offsets");
  expect_invalid([](BakeHierarchy* h) { h->grid_link_f.pop_back(); }, "grid_link_f");
  expect_invalid([](BakeHierarchy* h) { h->grid_link_node[0] = 99; }, "node 99 >= node count 8");
  expect_invalid([](BakeHierarchy* h) { h->grid_link_offsets.back() -= 1; }, "expected 0 to the link count");
}

TEST_F(BakeGridLinksIoTest, DamageIsRejectedOrRoundTrips) {
  const auto [accepted, rejected] = DamagePayloads(file_, {kGlnk}, 400, 11, path_ + ".again");
  std::printf("damaged GLNK payloads: %zu accepted, %zu rejected\n", accepted, rejected);
  EXPECT_GT(rejected, 0u);
  EXPECT_GT(accepted, 0u);  // factor bytes may take many values
  std::remove((path_ + ".again").c_str());
}

}  // namespace
}  // namespace relight
