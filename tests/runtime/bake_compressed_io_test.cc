// A compressed basis in the bake file (section CPCA, version 5,
// docs/bake-format.md): written only when a basis is compressed, read back
// exactly, every rule broken once through WriteBake (kInvalidArgument) and
// through the reader (kCorrupt naming the CPCA section), older versions
// refuse it, and random damage is rejected or round-trips.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "bake_file_edit.h"
#include "bake_test_bake.h"
#include "relight/bake/bake.h"
#include "relight/base/sh_index.h"

namespace relight {
namespace {

using namespace bake_test;  // NOLINT: test helpers

// META, MESH, GRID x 2, LUMI x 2, then 'spot' (exact: DIRT + BASE per set,
// 3 sets), then 'wash' (all in SH): its vertex BASE is entry 12.
constexpr size_t kWashVertices = 12;
constexpr uint32_t kComponents = 2;

// 11 vertices in two clusters [0, 6) and [6, 11) with two components.
BakeCompressedBasis MakeCompressed(int degree, uint32_t receivers) {
  std::mt19937 rng(3);
  BakeCompressedBasis c;
  c.components = kComponents;
  c.cluster_start = {0, 6, receivers};
  const size_t terms = static_cast<size_t>(ShTermCount(degree));
  for (size_t i = 0; i < 3 * terms * 2 * (kComponents + 1); ++i) {
    c.vectors.push_back(RandomInt<int16_t>(&rng, -32767, 32767));
  }
  for (size_t i = 0; i < 3 * terms; ++i) c.vector_scale.push_back(RandomScale(&rng));
  for (size_t i = 0; i < size_t{receivers} * kComponents; ++i) {
    c.weights.push_back(RandomInt<int16_t>(&rng, -kCompressedWeightOne, kCompressedWeightOne));
  }
  return c;
}

class BakeCompressedIoTest : public BakeFileTest {
 protected:
  void SetUp() override {
    BakeFileTest::SetUp();
    compressed_ = bake_;
    BakeLightReceivers& rx = compressed_.luminaires[1].receivers[0];
    rx.compressed = MakeCompressed(compressed_.luminaires[1].sh_degree, compressed_.mesh.vertex_count());
    rx.basis.clear();
    rx.basis_scale.clear();
    ASSERT_TRUE(WriteBake(compressed_, Path("cpca.rlb")).ok());
    cpca_file_ = ReadFileBytes(Path("cpca.rlb"));
  }

  void ExpectCorrupt(const Bytes& bytes, const std::string& part) {
    Bake out;
    const Status st = ParseBake(bytes.data(), bytes.size(), &out);
    EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
    EXPECT_TRUE(Contains(st.message(), "CPCA[lum 1 'wash', set 0]")) << st.message();
    EXPECT_TRUE(Contains(st.message(), part)) << "'" << st.message() << "' lacks '" << part << "'";
    EXPECT_TRUE(out.luminaires.empty());
  }
  Bytes Edit(const std::function<void(Bytes*)>& edit) { return EditPayload(cpca_file_, kWashVertices, edit); }
  // Byte offset of the weights' planes in the payload.
  size_t WeightsAt(const Bytes& p) const { return p.size() - 2 * 11 * kComponents; }

  Bake compressed_;
  Bytes cpca_file_;
};

TEST_F(BakeCompressedIoTest, ACompressedBasisMakesVersion5AndReadsBackExactly) {
  const Container c = Split(cpca_file_);
  EXPECT_EQ(c.version, 5u);
  EXPECT_EQ(c.sections[kWashVertices].tag, Tag("CPCA"));
  EXPECT_EQ(Split(file_).version, 3u);  // none compressed: as before
  Bake read;
  ASSERT_TRUE(ParseBake(cpca_file_.data(), cpca_file_.size(), &read).ok());
  ExpectBakesEqual(compressed_, read);
  EXPECT_TRUE(read.luminaires[1].receivers[0].compressed.present());
  EXPECT_FALSE(read.luminaires[1].receivers[1].compressed.present());
}

TEST_F(BakeCompressedIoTest, OlderVersionsRefuseTheSection) {
  Container c = Split(cpca_file_);
  c.version = 4;
  const Bytes v4 = Join(c);
  Bake out;
  const Status st = ParseBake(v4.data(), v4.size(), &out);
  EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "is CPCA, expected section BASE")) << st.message();
}

TEST_F(BakeCompressedIoTest, ReaderRejectsEveryBrokenRuleNamingTheSection) {
  const auto put32 = [](Bytes* p, size_t at, uint32_t v) { PutLe<uint32_t>(&(*p)[at], v); };
  ExpectCorrupt(Edit([&](Bytes* p) { put32(p, 0, 0); }), "0 clusters x 2 components");
  ExpectCorrupt(Edit([&](Bytes* p) { put32(p, 0, 12); }), "12 clusters x 2 components");
  ExpectCorrupt(Edit([&](Bytes* p) { put32(p, 0, 0xFFFFFFFFu); }), "4294967295 clusters");
  ExpectCorrupt(Edit([&](Bytes* p) { put32(p, 4, 65); }), "x 65 components");
  ExpectCorrupt(Edit([&](Bytes* p) { put32(p, 4, 3); }), "the counts need");
  ExpectCorrupt(Edit([&](Bytes* p) { put32(p, 12, 0); }), "cluster 0 is empty");
  ExpectCorrupt(Edit([&](Bytes* p) { put32(p, 12, 11); }), "cluster 1 is empty");
  ExpectCorrupt(Edit([&](Bytes* p) { put32(p, 16, 10); }), "cluster starts run from 0 to 10");
  ExpectCorrupt(Edit([&](Bytes* p) { put32(p, 8, 1); }), "cluster starts run from 1");
  ExpectCorrupt(Edit([&](Bytes* p) { put32(p, 20, 5); }), "vector_scale[term 0][channel 0]");
  ExpectCorrupt(Edit([&](Bytes* p) {
                  std::vector<int16_t> w = DecodePlanar<int16_t>(*p, WeightsAt(*p), 22, 1);
                  w[3] = kCompressedWeightOne + 1;
                  EncodePlanar(w, 1, p, WeightsAt(*p));
                }),
                "weight 3 is 16384");
  ExpectCorrupt(Edit([&](Bytes* p) { p->pop_back(); }), "CPCA");
  ExpectCorrupt(Edit([&](Bytes* p) { p->push_back(0); }), "CPCA");
}

// 8-bit weights (CPC8, version 8): the same basis with weights in [-127,
// 127] reads back exactly and half its weight bytes; version 7 refuses the
// section; a weight past 127 is corrupt in the file and refused by the writer.
TEST_F(BakeCompressedIoTest, EightBitWeightsMakeVersion8AndReadBackExactly) {
  Bake eight = compressed_;
  BakeCompressedBasis& c = eight.luminaires[1].receivers[0].compressed;
  c.weight_bits = 8;
  for (int16_t& w : c.weights) w = static_cast<int16_t>(w / 129);  // [-127, 127]
  c.weights[0] = -kCompressedWeightOne8;
  c.weights[1] = kCompressedWeightOne8;
  ASSERT_TRUE(WriteBake(eight, Path("cpc8.rlb")).ok());
  const Bytes file = ReadFileBytes(Path("cpc8.rlb"));
  Container k = Split(file);
  EXPECT_EQ(k.version, 8u);
  EXPECT_EQ(k.sections[kWashVertices].tag, Tag("CPC8"));
  EXPECT_EQ(k.sections[kWashVertices].raw + 11 * kComponents,
            Split(cpca_file_).sections[kWashVertices].raw);  // a byte a weight
  Bake read;
  ASSERT_TRUE(ParseBake(file.data(), file.size(), &read).ok());
  ExpectBakesEqual(eight, read);

  k.version = 7;
  const Bytes v7 = Join(k);
  Bake out;
  Status st = ParseBake(v7.data(), v7.size(), &out);
  EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "is CPC8, expected section BASE")) << st.message();

  const Bytes bad = EditPayload(file, kWashVertices, [&](Bytes* p) {
    const size_t at = p->size() - 11 * kComponents;
    std::vector<int8_t> w = DecodePlanar<int8_t>(*p, at, 22, 1);
    w[3] = -128;
    EncodePlanar(w, 1, p, at);
  });
  st = ParseBake(bad.data(), bad.size(), &out);
  EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "CPC8[lum 1 'wash', set 0]")) << st.message();
  EXPECT_TRUE(Contains(st.message(), "weight 3 is -128, outside [-127, 127] (8-bit weights)")) << st.message();

  c.weights[2] = 200;
  st = WriteBake(eight, Path("cpc8.rlb"));
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "weight 2 is 200")) << st.message();
  EXPECT_EQ(ReadFileBytes(Path("cpc8.rlb")), file) << "the old file stays";
}

TEST_F(BakeCompressedIoTest, RandomDamageIsRejectedOrRoundTrips) {
  const auto [accepted, rejected] = DamagePayloads(cpca_file_, {kWashVertices}, 300, 11, Path("scratch.rlb"));
  EXPECT_GT(rejected, 0u);
  EXPECT_EQ(accepted + rejected, 300u);
}

TEST_F(BakeCompressedIoTest, WriterRejectsEveryBrokenRuleAndKeepsTheOldFile) {
  bake_ = compressed_;
  file_ = cpca_file_;
  ASSERT_TRUE(WriteBake(bake_, Path("good.rlb")).ok());
  std::filesystem::remove(Path("cpca.rlb"));  // the directory holds good.rlb alone
  using C = BakeCompressedBasis;
  const auto cpca = [](const std::function<void(C*)>& f) {
    return [f](Bake* b) { f(&b->luminaires[1].receivers[0].compressed); };
  };
  ExpectWriteRejects({
      {"has both a basis and a compressed basis",
       [](Bake* b) { b->luminaires[1].receivers[0].basis.push_back(0); }},
      {"65 components", cpca([](C* c) { c->components = 65; })},
      {"cluster 0 is empty", cpca([](C* c) { c->cluster_start[1] = 0; })},
      {"cluster starts run from 0 to 12", cpca([](C* c) { c->cluster_start[2] = 12; })},
      {"weights has 21 values", cpca([](C* c) { c->weights.pop_back(); })},
      {"vectors has", cpca([](C* c) { c->vectors.pop_back(); })},
      {"weight 0 is -16384", cpca([](C* c) { c->weights[0] = -16384; })},
      {"zero scale but vector", cpca([](C* c) { c->vector_scale[0] = QuantScale{}; })},
  });
}

}  // namespace
}  // namespace relight
