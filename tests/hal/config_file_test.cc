// Issue 17: the patch and the DMX patch are read bounded: /dev/zero, a FIFO
// nobody writes to, a directory or an oversized file is a clear error naming
// the file, never a hang or memory growing without end.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include "relight/hal/dmx/dmx_patch.h"
#include "relight/hal/patch.h"

namespace relight::hal {
namespace {

Status LoadBoth(const std::string& path) {
  Patch patch;
  const Status st = LoadPatch(path, &patch);
  DmxPatch dmx;
  const Status dmx_st = LoadDmxPatch(path, &dmx);
  EXPECT_EQ(st.code(), dmx_st.code()) << st.ToString() << " / " << dmx_st.ToString();
  EXPECT_NE(dmx_st.message().find("DMX patch '" + path + "'"), std::string::npos) << dmx_st.ToString();
  return st;
}

TEST(ConfigFile, DevZeroIsNotARegularFile) {
  const Status st = LoadBoth("/dev/zero");
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("patch '/dev/zero': not a regular file"), std::string::npos) << st.ToString();
}

TEST(ConfigFile, AFifoDoesNotBlock) {
  const std::string fifo = ::testing::TempDir() + "/config_file_test.fifo";
  unlink(fifo.c_str());
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  const Status st = LoadBoth(fifo);  // nobody writes: a blocking open would hang here
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("not a regular file"), std::string::npos) << st.ToString();
  unlink(fifo.c_str());
}

TEST(ConfigFile, ADirectoryAndAMissingFile) {
  EXPECT_EQ(LoadBoth(::testing::TempDir()).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(LoadBoth("/nonexistent/patch.toml").code(), StatusCode::kNotFound);
}

TEST(ConfigFile, OverTheLimit) {
  const std::string big = ::testing::TempDir() + "/config_file_test_big.toml";
  {
    std::ofstream out(big, std::ios::binary);
    const std::string line(1023, '#');
    for (int i = 0; i < 4 * 1024 + 1; ++i) out << line << '\n';  // just over 4 MiB of comments
  }
  const Status st = LoadBoth(big);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("more than the limit of 4194304"), std::string::npos) << st.ToString();
  unlink(big.c_str());
}

}  // namespace
}  // namespace relight::hal
