// SH degrees above 16 (format version 7, issue 12: the narrowest zooms of
// real fixture types need degree 22): a bake with one is stamped version 7
// and reads back exactly; without one it keeps its old version; a file that
// claims an older version with such a degree is corrupt, naming LUMI and the
// versions; past kMaxShDegree is rejected on write.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

#include <unistd.h>

#include "bake_file_edit.h"
#include "bake_test_bake.h"
#include "relight/bake/bake.h"

namespace relight {
namespace {

using namespace bake_test;  // NOLINT: test helpers


// MakeBake's "wash" (luminaire 1, all in SH) at `degree`, with bases to match.
Bake WithWashDegree(int degree) {
  Bake b = MakeBake(7);
  std::mt19937 rng(99);
  BakeLuminaire& wash = b.luminaires[1];
  wash.sh_degree = static_cast<uint8_t>(degree);
  wash.receivers.clear();
  for (uint32_t s = 0; s < b.receiver_set_count(); ++s) {
    wash.receivers.push_back(MakeReceivers(&rng, wash, b.receiver_count(s)));
  }
  return b;
}

class BakeHighDegreeIoTest : public ::testing::Test {
 protected:
  // One file per test and process: ctest -j runs this binary's tests at once.
  void SetUp() override {
    path_ = ::testing::TempDir() + "bake_high_degree_io_test_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name() + "_" + std::to_string(getpid()) + ".rlb";
  }
  void TearDown() override { std::remove(path_.c_str()); }
  std::string path_;
};

TEST_F(BakeHighDegreeIoTest, Degree22RoundTripsAsVersion7) {
  const Bake b = WithWashDegree(kMaxShDegree);
  ASSERT_EQ(kMaxShDegree, 22);
  ASSERT_TRUE(WriteBake(b, path_).ok());
  const Bytes file = ReadFileBytes(path_);
  EXPECT_EQ(Split(file).version, 7u);
  Bake back;
  ASSERT_TRUE(ReadBake(path_, &back).ok());
  ExpectBakesEqual(b, back);
  // Degree 16 (the old maximum) keeps the lowest version that holds the bake.
  ASSERT_TRUE(WriteBake(WithWashDegree(16), path_).ok());
  EXPECT_EQ(Split(ReadFileBytes(path_)).version, 3u);
}

TEST_F(BakeHighDegreeIoTest, AnOlderVersionWithDegreeAbove16IsCorrupt) {
  ASSERT_TRUE(WriteBake(WithWashDegree(17), path_).ok());
  Container c = Split(ReadFileBytes(path_));
  ASSERT_EQ(c.version, 7u);
  c.version = 6;
  Bake out;
  const Bytes bytes = Join(c);
  const Status st = ParseBake(bytes.data(), bytes.size(), &out);
  EXPECT_EQ(st.code(), StatusCode::kCorrupt) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "section LUMI[1]: SH degree 17 needs format version 7, the file has 6"))
      << st.message();
}

TEST_F(BakeHighDegreeIoTest, PastTheMaximumIsRefusedOnWrite) {
  const Status st = WriteBake(WithWashDegree(kMaxShDegree + 1), path_);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << st.ToString();
  EXPECT_TRUE(Contains(st.message(), "SH degree 23 exceeds the maximum 22")) << st.message();
}

}  // namespace
}  // namespace relight
