// Handing read-only file pages back to the kernel (compiler_pages.h): a
// file of our own mapped read-only leaves the process's resident set and
// still reads the same; a writable mapping of the same file keeps its
// written bytes (it is never advised).
#include "relight/render/compiler_pages.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "common/smaps.h"

namespace relight::render {
namespace {

constexpr size_t kFileBytes = size_t{8} << 20;

// Rss (kB) of the mapping that starts at `addr`; -1 if absent.
long MappingRssKb(const void* addr) {
  const test::SmapsKb kb = test::SmapsAt(addr);
  return kb.any ? kb.rss : -1;
}

uint64_t Checksum(const uint8_t* p, size_t n) {
  uint64_t h = 1469598103934665603u;
  for (size_t i = 0; i < n; i += 512) h = (h ^ p[i]) * 1099511628211u;
  return h;
}

class CompilerPages : public ::testing::Test {
 protected:
  void SetUp() override {
    // In the working directory (ctest: the build tree), not TempDir(): a
    // tmpfs file's pages have nowhere to go without swap.
    path_ = "./relight_compiler_pages_test_" + std::to_string(getpid()) + ".bin";
    std::vector<uint8_t> bytes(kFileBytes);
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<uint8_t>((i * 2654435761u) >> 13);
    expected_ = Checksum(bytes.data(), bytes.size());
    fd_ = open(path_.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    ASSERT_GE(fd_, 0) << path_;
    ASSERT_EQ(write(fd_, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
    ASSERT_EQ(fsync(fd_), 0);  // clean pages: reclaimable at once
  }
  void TearDown() override {
    if (fd_ >= 0) close(fd_);
    unlink(path_.c_str());
  }

  std::string path_;
  int fd_ = -1;
  uint64_t expected_ = 0;
};

TEST_F(CompilerPages, ReadOnlyMappingLeavesTheResidentSetAndReadsTheSame) {
  void* map = mmap(nullptr, kFileBytes, PROT_READ, MAP_PRIVATE, fd_, 0);
  ASSERT_NE(map, MAP_FAILED);
  const auto* bytes = static_cast<const uint8_t*>(map);
  ASSERT_EQ(Checksum(bytes, kFileBytes), expected_);  // touches every page
  const long before_kb = MappingRssKb(map);
  ASSERT_GE(before_kb, static_cast<long>(kFileBytes / 1024 * 9 / 10));

  PagesReleased released;
  const std::string name = path_.substr(path_.rfind('/') + 1);
  const Status st = ReleaseMappedFilePages(name.c_str(), &released);
  if (st.code() == StatusCode::kUnsupported) GTEST_SKIP() << st.ToString();
  ASSERT_TRUE(st.ok()) << st.ToString();
  EXPECT_EQ(released.mappings, 1);
  EXPECT_EQ(released.bytes, kFileBytes);
  const long after_kb = MappingRssKb(map);
  EXPECT_LT(after_kb, before_kb / 4) << "resident before " << before_kb << " kB";

  EXPECT_EQ(Checksum(bytes, kFileBytes), expected_);  // read back from the file
  munmap(map, kFileBytes);
}

TEST_F(CompilerPages, WritableMappingKeepsWhatWasWritten) {
  void* map = mmap(nullptr, kFileBytes, PROT_READ | PROT_WRITE, MAP_PRIVATE, fd_, 0);
  ASSERT_NE(map, MAP_FAILED);
  auto* bytes = static_cast<uint8_t*>(map);
  for (size_t i = 0; i < kFileBytes; i += 4096) bytes[i] = static_cast<uint8_t>(i >> 12);
  const uint64_t written = Checksum(bytes, kFileBytes);
  ASSERT_NE(written, expected_);

  PagesReleased released;
  const std::string name = path_.substr(path_.rfind('/') + 1);
  const Status st = ReleaseMappedFilePages(name.c_str(), &released);
  if (st.code() == StatusCode::kUnsupported) GTEST_SKIP() << st.ToString();
  ASSERT_TRUE(st.ok()) << st.ToString();
  EXPECT_EQ(released.mappings, 0);
  EXPECT_EQ(Checksum(bytes, kFileBytes), written);
  munmap(map, kFileBytes);
}

TEST(CompilerPagesArgs, AnEmptyNameIsRefusedAndNoMatchIsNoError) {
  PagesReleased released;
  EXPECT_EQ(ReleaseMappedFilePages("", &released).code(), StatusCode::kInvalidArgument);
  const Status st = ReleaseMappedFilePages("no-such-library-is-mapped-here.so", &released);
  EXPECT_TRUE(st.ok()) << st.ToString();
  EXPECT_EQ(released.mappings, 0);
  EXPECT_EQ(released.bytes, 0u);
}

}  // namespace
}  // namespace relight::render
