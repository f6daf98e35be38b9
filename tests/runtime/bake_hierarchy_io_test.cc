// The stored radiosity hierarchy (sections HIER and LINK, format version 3):
// every validation rule broken once, through WriteBake (kInvalidArgument)
// and through the reader (kCorrupt, naming the section), the version and
// section-count rules, and damage confined to the two sections. Round trips
// and whole-file truncation and bit flips run in bake_io_test.cc, whose
// test bake carries a hierarchy too.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "bake_file_edit.h"
#include "bake_test_bake.h"
#include "relight/bake/bake.h"

namespace relight {
namespace {

using namespace bake_test;  // NOLINT: test helpers

constexpr size_t kNodes = 8, kLinks = 7;       // AddHierarchy's
constexpr size_t kHier = 15, kLink = 16;       // their TOC entries in MakeBake's file
constexpr uint32_t kNo = kBakeNoIndex;

class BakeHierarchyIoTest : public BakeFileTest {
 protected:
  void SetUp() override {
    BakeFileTest::SetUp();
    ASSERT_TRUE(bake_.hierarchy.has_value());
    const Container c = Split(file_);
    ASSERT_EQ(c.sections.size(), kLink + 1);
    ASSERT_EQ(c.sections[kHier].tag, Tag("HIER"));
    ASSERT_EQ(c.sections[kLink].tag, Tag("LINK"));
  }

  void ExpectCorrupt(const Bytes& bytes, const std::string& part) {
    Bake out;
    const Status st = ParseBake(bytes.data(), bytes.size(), &out);
    EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
    EXPECT_TRUE(Contains(st.message(), part)) << "'" << st.message() << "' lacks '" << part << "'";
    EXPECT_FALSE(out.hierarchy.has_value());
  }
};

TEST_F(BakeHierarchyIoTest, WriteReportsEverySectionSizeInFileOrder) {
  std::vector<BakeSectionSize> sizes;
  ASSERT_TRUE(WriteBake(bake_, Path("again.rlb"), &sizes).ok());
  const Container c = Split(file_);
  ASSERT_EQ(sizes.size(), c.sections.size());
  for (size_t i = 0; i < c.sections.size(); ++i) {
    EXPECT_EQ(Tag(sizes[i].tag), c.sections[i].tag) << i;
    EXPECT_EQ(sizes[i].raw_bytes, c.sections[i].raw) << i;
    EXPECT_EQ(sizes[i].stored_bytes, c.sections[i].stored) << i;
  }
  // docs/bake-format.md: 4 + 48 bytes per node, 4 + 32 per link.
  EXPECT_EQ(sizes[kHier].raw_bytes, 4 + 48 * kNodes);
  EXPECT_EQ(sizes[kLink].raw_bytes, 4 + 32 * kLinks);
}

// Readers that predate HIER and LINK still read a bake without them.
TEST_F(BakeHierarchyIoTest, WithoutAHierarchyTheFileIsVersion2) {
  Bake plain = bake_;
  plain.hierarchy.reset();
  ASSERT_TRUE(WriteBake(plain, Path("plain.rlb")).ok());
  const Bytes bytes = ReadFileBytes(Path("plain.rlb"));
  const Container c = Split(bytes);
  EXPECT_EQ(c.version, 2u);
  EXPECT_EQ(c.sections.size(), kHier);
  Bake read;
  ASSERT_TRUE(ParseBake(bytes.data(), bytes.size(), &read).ok());
  EXPECT_FALSE(read.hierarchy.has_value());
  ExpectBakesEqual(plain, read);
}

TEST_F(BakeHierarchyIoTest, SectionsComeTogetherAfterTheBasesInVersion3) {
  Container c = Split(file_);
  c.version = 2;
  ExpectCorrupt(Join(c), "17 sections, the counts need 15 (HIER and LINK need format version 3");
  c = Split(file_);
  c.sections.pop_back();
  Relayout(&c);
  ExpectCorrupt(Join(c), "16 sections, the counts need 15 (or 17 with HIER and LINK)");
  c = Split(file_);
  std::swap(c.sections[kHier], c.sections[kLink]);
  Relayout(&c);
  ExpectCorrupt(Join(c), "TOC entry 15: is LINK, expected section HIER");
  c = Split(file_);
  c.sections[kLink].tag = Tag("BASE");
  ExpectCorrupt(Join(c), "TOC entry 16: is BASE, expected section LINK");
}

TEST_F(BakeHierarchyIoTest, SectionSizesMustMatchTheirCounts) {
  // 2 T = 16 nodes cannot come from 8 triangles: refused before decompressing.
  ExpectCorrupt(EditPayload(file_, kHier, [](Bytes* p) { p->resize(4 + 48 * 16, 0); }, true),
                "section HIER: raw size 772 is outside [52, 724] for the counts");
  ExpectCorrupt(EditPayload(file_, kHier, [](Bytes* p) { PutLe<uint32_t>(p->data(), 7); }),
                "section HIER: 7 nodes need 340 bytes, the section has 388");
  ExpectCorrupt(EditPayload(file_, kHier, [](Bytes* p) { p->resize(3); }),
                "section HIER: raw size 3 is outside");
  ExpectCorrupt(EditPayload(file_, kLink, [](Bytes* p) { PutLe<uint32_t>(p->data(), 8); }),
                "section LINK: 8 links need 260 bytes, the section has 228");
  ExpectCorrupt(EditPayload(file_, kLink, [](Bytes* p) { p->resize(2); }),
                "section LINK: raw size 2 is outside");
}

// HIER payload: count, then planar arrays (docs/bake-format.md).
constexpr size_t kSurfaceAt = 4, kParentAt = kSurfaceAt + 2 * kNodes,
                 kFirstChildAt = kParentAt + 4 * kNodes, kChildCountAt = kFirstChildAt + 4 * kNodes,
                 kCornerCountAt = kChildCountAt + kNodes, kCornersAt = kCornerCountAt + kNodes,
                 kAreaAt = kCornersAt + 24 * kNodes, kLeafTriangleAt = kAreaAt + 8 * kNodes;
// LINK payload.
constexpr size_t kPAt = 4, kQAt = kPAt + 4 * kLinks, kFpqAt = kQAt + 4 * kLinks,
                 kFqpAt = kFpqAt + 4 * kLinks, kGpqAt = kFqpAt + 4 * kLinks,
                 kGqpAt = kGpqAt + 8 * kLinks;

template <typename T>
Bytes EditArray(const Bytes& file, size_t section, size_t at, size_t n, size_t stride,
                const std::function<void(std::vector<T>*)>& edit) {
  return EditPayload(file, section, [&](Bytes* p) {
    std::vector<T> v = DecodePlanar<T>(*p, at, n, stride);
    edit(&v);
    EncodePlanar(v, stride, p, at);
  });
}

TEST_F(BakeHierarchyIoTest, ReaderNamesTheSectionAndTheOffendingIndex) {
  ExpectCorrupt(EditArray<uint16_t>(file_, kHier, kSurfaceAt, kNodes, 1,
                                    [](auto* v) { (*v)[7] = 3; }),
                "section HIER: node 7: surface 3 >= surface count 3");
  ExpectCorrupt(EditArray<uint32_t>(file_, kHier, kParentAt, kNodes, 1,
                                    [](auto* v) { (*v)[4] = 0; }),
                "section HIER: node 2: child 4 names node 0 as its parent");
  ExpectCorrupt(EditArray<uint32_t>(file_, kHier, kCornersAt, 6 * kNodes, 6,
                                    [](auto* v) { (*v)[6 * 6 + 2] = 11; }),
                "section HIER: node 6: corner 2: vertex index 11 >= vertex count 11");
  ExpectCorrupt(EditArray<uint64_t>(file_, kHier, kAreaAt, kNodes, 1,
                                    [](auto* v) { (*v)[0] += 1; }),
                "section HIER: node 0: area");
  ExpectCorrupt(EditArray<uint32_t>(file_, kHier, kLeafTriangleAt, kNodes, 1,
                                    [](auto* v) { (*v)[7] = 9; }),
                "section HIER: node 7: leaf triangles [9, 10) run past the triangle count 8");
  ExpectCorrupt(EditArray<uint8_t>(file_, kHier, kChildCountAt, kNodes, 1,
                                   [](auto* v) { (*v)[2] = 1; }),
                "section HIER: node 2: 1 child; an inner node has at least 2");
  ExpectCorrupt(EditArray<uint8_t>(file_, kHier, kCornerCountAt, kNodes, 1,
                                   [](auto* v) { (*v)[3] = 7; }),
                "section HIER: node 3: 7 corners, expected 3 to 6");
  ExpectCorrupt(EditArray<uint32_t>(file_, kHier, kFirstChildAt, kNodes, 1,
                                    [](auto* v) { (*v)[2] = 4; }),
                "section HIER: node 2: children start at node 4, expected 3");
  ExpectCorrupt(EditArray<uint32_t>(file_, kLink, kQAt, kLinks, 1, [](auto* v) { (*v)[6] = 8; }),
                "section LINK: link 6: node 8 >= node count 8");
  ExpectCorrupt(EditArray<uint32_t>(file_, kLink, kPAt, kLinks, 1, [](auto* v) { (*v)[3] = 1; }),
                "section LINK: link 3: (1, 6) does not come after (1, 6)");
  ExpectCorrupt(EditArray<uint32_t>(file_, kLink, kFpqAt, kLinks, 1, [](auto* v) { (*v)[0] = 0; }),
                "section LINK: link 0: gradient");
  ExpectCorrupt(EditArray<int32_t>(file_, kLink, kGqpAt, 2 * kLinks, 2,
                                   [](auto* v) { (*v)[3] = -1; }),
                "section LINK: link 1: gradient (0, -1) over node 7, which is a leaf");
  ExpectCorrupt(EditArray<uint32_t>(file_, kLink, kFqpAt, kLinks, 1, [](auto* v) { (*v)[4] = 0; }),
                "section LINK: link 4: both factors are 0");
  ExpectCorrupt(EditPayload(file_, kLink, [](Bytes* p) { p->push_back(0); }),
                "section LINK: 7 links need 228 bytes, the section has 229");
}

// Issue 17: each factor is at most 1 by its format, but what a receiver
// gathers (its links and its ancestors') must be a form factor sum too
// (<= 2), or the fixed-point emitter solve's gathers are not provably safe.
TEST_F(BakeHierarchyIoTest, ReceiverFormFactorSumsAreBounded) {
  // Links 0, 2, 3 and 6 all send to leaf 6: four factors of 1 are 4.
  ExpectCorrupt(EditArray<uint32_t>(file_, kLink, kFqpAt, kLinks, 1,
                                    [](auto* v) { (*v)[0] = (*v)[2] = (*v)[3] = (*v)[6] = UINT32_MAX; }),
                "section LINK: node 6: its links and its ancestors' gather form factors summing to "
                "3.99");
  // Node 0 gathers links 0 and 1 (2 - 2^-31: allowed); its child 1 gathers
  // them again with its own link 2.
  ExpectCorrupt(EditArray<uint32_t>(file_, kLink, kFpqAt, kLinks, 1,
                                    [](auto* v) { (*v)[0] = (*v)[1] = (*v)[2] = UINT32_MAX; }),
                "section LINK: node 1: its links and its ancestors' gather form factors summing to "
                "2.99");
  // One factor of 1 (2^32 - 1), alone on its receiver, is a valid bake.
  const Bytes one = EditArray<uint32_t>(file_, kLink, kFqpAt, kLinks, 1, [](auto* v) {
    (*v)[0] = UINT32_MAX, (*v)[2] = (*v)[3] = (*v)[6] = 1;
  });
  Bake out;
  EXPECT_TRUE(ParseBake(one.data(), one.size(), &out).ok());
}

// Node 2 keeps children 3 and 4 only; the areas still add up.
void DropLastChildOfNode2(BakeHierarchy* h) {
  h->node_child_count[2] = 2;
  h->node_area[2] -= h->node_area[5];
  h->node_area[0] -= h->node_area[5];
}

// Every rule of bake_check_hierarchy.cc, broken once in an otherwise valid bake.
TEST_F(BakeHierarchyIoTest, WriteRejectsEveryBrokenRuleAndNamesTheIndex) {
  const auto h = [](Bake* b) -> BakeHierarchy& { return *b->hierarchy; };
  ExpectWriteRejects({
      // Array lengths and counts.
      {"hierarchy nodes: node_area has 7 values, expected nodes = 8",
       [&](Bake* b) { h(b).node_area.pop_back(); }},
      {"hierarchy nodes: node_corners has 47 values, expected 6 x nodes = 48",
       [&](Bake* b) { h(b).node_corners.pop_back(); }},
      {"hierarchy nodes: node_parent has 9 values",
       [&](Bake* b) { h(b).node_parent.push_back(0); }},
      {"hierarchy nodes: no nodes", [&](Bake* b) { b->hierarchy = BakeHierarchy(); }},
      {"hierarchy nodes: 16 nodes, but 8 triangles allow at most 2 x triangles - 1",
       [&](Bake* b) {
         BakeHierarchy& x = h(b);
         for (size_t k = 0; k < kNodes; ++k) {
           x.node_surface.push_back(2);
           x.node_parent.push_back(kNo);
           x.node_first_child.push_back(kNo);
           x.node_child_count.push_back(0);
           x.node_corner_count.push_back(3);
           x.node_corners.insert(x.node_corners.end(), {0, 1, 2, kNo, kNo, kNo});
           x.node_area.push_back(1);
           x.node_leaf_triangle.push_back(0);
         }
       }},
      // Surfaces and tree structure.
      {"hierarchy nodes: node 7: surface 3 >= surface count 3",
       [&](Bake* b) { h(b).node_surface[7] = 3; }},
      {"hierarchy nodes: node 7: surface 1 comes after surface 2",
       [&](Bake* b) {
         h(b).node_surface[6] = 2, h(b).node_surface[7] = 1;
         b->mesh.triangle_surface[5] = b->mesh.triangle_surface[6] = 2;
         b->mesh.triangle_surface[7] = 1;
       }},
      {"hierarchy nodes: node 6: the first node of surface 1 has parent 0",
       [&](Bake* b) { h(b).node_parent[6] = 0; }},
      // Node 5 taken out of node 2's children (areas kept consistent), then given a parent.
      {"hierarchy nodes: node 5: is not among the children of its parent 2",
       [&](Bake* b) { DropLastChildOfNode2(&h(b)); }},
      {"hierarchy nodes: node 5: a second root on surface 0",
       [&](Bake* b) { DropLastChildOfNode2(&h(b)), h(b).node_parent[5] = kNo; }},
      {"hierarchy nodes: node 5: parent 6 is not an earlier node of surface 0",
       [&](Bake* b) { DropLastChildOfNode2(&h(b)), h(b).node_parent[5] = 6; }},
      {"hierarchy nodes: node 2: child 4 names node 0 as its parent",
       [&](Bake* b) { h(b).node_parent[4] = 0; }},
      {"hierarchy nodes: node 7: a leaf with first child 3",
       [&](Bake* b) { h(b).node_first_child[7] = 3; }},
      {"hierarchy nodes: node 2: 1 child; an inner node has at least 2",
       [&](Bake* b) { h(b).node_child_count[2] = 1; }},
      {"hierarchy nodes: node 0: an inner node with leaf triangle 0",
       [&](Bake* b) { h(b).node_leaf_triangle[0] = 0; }},
      {"hierarchy nodes: node 2: children start at node 4, expected 3",
       [&](Bake* b) { h(b).node_first_child[2] = 4; }},
      {"hierarchy nodes: node 2: children [3, 9) run past the node count 8",
       [&](Bake* b) { h(b).node_child_count[2] = 6; }},
      // Corners.
      {"hierarchy nodes: node 1: 2 corners, expected 3 to 6",
       [&](Bake* b) { h(b).node_corner_count[1] = 2; }},
      {"hierarchy nodes: node 3: unused corner slot 3 holds 5, not 0xFFFFFFFF",
       [&](Bake* b) { h(b).node_corners[6 * 3 + 3] = 5; }},
      {"hierarchy nodes: node 0: corner 0: vertex index 11 >= vertex count 11",
       [&](Bake* b) { h(b).node_corners[0] = 11; }},
      {"hierarchy nodes: node 0: corners 0 and 2 are both vertex 0",
       [&](Bake* b) { h(b).node_corners[2] = 0; }},
      // Areas.
      {"hierarchy nodes: node 6: area 0 (Q32.32 m^2) is outside [1, 2^56]",
       [&](Bake* b) { h(b).node_area[6] = 0; }},
      {"hierarchy nodes: node 7: area 72057594037927937 (Q32.32 m^2) is outside [1, 2^56]",
       [&](Bake* b) { h(b).node_area[7] = (uint64_t{1} << 56) + 1; }},
      {"hierarchy nodes: node 0: area", [&](Bake* b) { h(b).node_area[0] += 1; }},
      // Leaves and their triangles.
      {"hierarchy nodes: node 7: leaf triangles [8, 9) run past the triangle count 8",
       [&](Bake* b) { h(b).node_leaf_triangle[7] = 8; }},
      {"hierarchy nodes: node 1: triangle 0 is (0, 1, 2), not (0, 1, 3) of the fan",
       [&](Bake* b) { std::swap(h(b).node_corners[6 + 2], h(b).node_corners[6 + 3]); }},
      {"hierarchy nodes: node 7: triangle 7 is on surface 1, the node on surface 2",
       [](Bake* b) { b->mesh.triangle_surface[7] = 1; }},
      {"hierarchy nodes: node 4: triangle 2 is in another leaf too",
       [&](Bake* b) {
         BakeHierarchy& x = h(b);
         x.node_leaf_triangle[4] = 2;
         for (int k = 0; k < 3; ++k) x.node_corners[6 * 4 + k] = x.node_corners[6 * 3 + k];
       }},
      {"hierarchy nodes: triangle 8 is in no leaf",
       [](Bake* b) {
         b->mesh.triangles.insert(b->mesh.triangles.end(), {0, 1, 2});
         b->mesh.triangle_surface.push_back(0);
       }},
      // Links.
      {"hierarchy links: link_g_qp has 13 values, expected 2 x links = 14",
       [&](Bake* b) { h(b).link_g_qp.pop_back(); }},
      {"hierarchy links: link_q has 6 values, expected links = 7",
       [&](Bake* b) { h(b).link_q.pop_back(); }},
      {"hierarchy links: link 0: node 8 >= node count 8", [&](Bake* b) { h(b).link_q[0] = 8; }},
      {"hierarchy links: link 0: p 6 is not below q 0",
       [&](Bake* b) { std::swap(h(b).link_p[0], h(b).link_q[0]); }},
      {"hierarchy links: link 1: (0, 6) does not come after (0, 6) (sorted by p, then q, no "
       "repeats)",
       [&](Bake* b) { h(b).link_q[1] = 6; }},
      {"hierarchy links: link 3: (1, 5) does not come after (1, 6)",
       [&](Bake* b) { h(b).link_p[3] = 1, h(b).link_q[3] = 5; }},
      {"hierarchy links: link 0: nodes 0 and 2 are both on surface 0",
       [&](Bake* b) { h(b).link_q[0] = 2; }},
      {"hierarchy links: link 5: both factors are 0",
       [&](Bake* b) { h(b).link_f_pq[5] = 0, h(b).link_f_qp[5] = 0; }},
      {"hierarchy links: link 2: gradient (7, 0) over node 1, which is a leaf",
       [&](Bake* b) { h(b).link_g_pq[4] = 7; }},
      {"hierarchy links: link 0: gradient (0, 3) over node 6, which is a leaf",
       [&](Bake* b) { h(b).link_g_qp[1] = 3; }},
      {"hierarchy links: link 4: gradient (9, 0) over node 2, which gets a zero factor",
       [&](Bake* b) { h(b).link_g_pq[8] = 9; }},
  });
}

// Bit flips in the two sections break their crcs; random bytes behind valid
// crcs are rejected as corrupt or, if every rule still holds, round-trip.
TEST_F(BakeHierarchyIoTest, DamageToTheSectionsIsRejectedOrRoundTrips) {
  const Container c = Split(file_);
  for (size_t section : {kHier, kLink}) {
    const Section& s = c.sections[section];
    for (size_t at = s.offset; at < s.offset + s.stored; ++at) {
      Bytes bad = file_;
      bad[at] = static_cast<uint8_t>(bad[at] ^ (1u << (at % 8)));
      ExpectCorrupt(bad, "crc mismatch");
      if (HasFailure()) return;
    }
  }
  const auto [accepted, rejected] =
      DamagePayloads(file_, {kHier, kLink}, 600, 5, Path("again.rlb"));
  std::printf("damaged HIER/LINK payloads: %zu accepted (values still in range), %zu rejected\n",
              accepted, rejected);
  EXPECT_GT(rejected, 0u);
  EXPECT_GT(accepted, 0u);  // factor and gradient bytes may take any value
}

}  // namespace
}  // namespace relight
