// Issue 17: files named by the user or by another input (scene, OBJ, mtllib,
// photometric file, IES TILT=<file>) are read only when they are regular
// files under a size limit; /dev/zero, a FIFO, a directory or a huge file is
// a clear error naming the path, never a hang or an unbounded allocation.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>

#include "bounded_read.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/scene.h"

namespace relight::baker {
namespace {

class BoundedRead : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::testing::TempDir() + "relight_bounded_XXXXXX";
    ASSERT_NE(mkdtemp(dir_.data()), nullptr);
    fifo_ = dir_ + "/pipe";
    ASSERT_EQ(mkfifo(fifo_.c_str(), 0600), 0);
  }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  void Write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ + "/" + name, std::ios::binary) << text;
  }
  // Loads the scene and returns the error; fails the test if it loads.
  std::string SceneErrorOf(const std::string& toml) {
    Write("s.toml", toml);
    try {
      LoadScene(dir_ + "/s.toml");
    } catch (const SceneError& e) {
      return e.what();
    }
    ADD_FAILURE() << "accepted";
    return "";
  }
  static std::string Head() {
    return "[scene]\nname = \"t\"\n[camera]\nposition = [1, 1, 1]\ntarget = [0, 0, 0]\n"
           "fov = 50\n";  // 6 lines
  }

  std::string dir_, fifo_;
};

TEST_F(BoundedRead, RegularFileUnderTheLimitIsRead) {
  Write("a.txt", "hello\n");
  std::string text, why;
  ASSERT_TRUE(ReadBoundedFile(dir_ + "/a.txt", 6, &text, &why)) << why;
  EXPECT_EQ(text, "hello\n");
}

TEST_F(BoundedRead, RefusesDevicesFifosDirectoriesAndLargeFiles) {
  const auto start = std::chrono::steady_clock::now();
  const auto refused = [](const std::string& path, std::uint64_t limit, const std::string& part) {
    std::string text, why;
    EXPECT_FALSE(ReadBoundedFile(path, limit, &text, &why)) << path;
    EXPECT_NE(why.find("'" + path + "'"), std::string::npos) << why;
    EXPECT_NE(why.find(part), std::string::npos) << why;
    EXPECT_TRUE(text.empty());
  };
  refused("/dev/zero", kMaxPhotometricFileBytes, "is a character device, not a regular file");
  refused(fifo_, kMaxPhotometricFileBytes, "is a FIFO (named pipe), not a regular file");
  refused(dir_, kMaxPhotometricFileBytes, "is a directory, not a regular file");
  refused(dir_ + "/none", kMaxPhotometricFileBytes, "cannot open");
  // A sparse 5 MiB file: one byte over the photometric limit is refused by its size.
  const std::string big = dir_ + "/big.ies";
  Write("big.ies", "");
  ASSERT_EQ(truncate(big.c_str(), static_cast<off_t>(kMaxPhotometricFileBytes + 1)), 0);
  refused(big, kMaxPhotometricFileBytes, "bytes, more than the 4 MiB limit");
  // Nothing above waited for a writer or read to the end of a device.
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
}

TEST_F(BoundedRead, PhotometricFileThatIsAFifoOrDevZero) {
  ASSERT_EQ(symlink("/dev/zero", (dir_ + "/zero.ies").c_str()), 0);
  ASSERT_EQ(symlink(fifo_.c_str(), (dir_ + "/pipe.ldt").c_str()), 0);
  for (const char* name : {"/zero.ies", "/pipe.ldt"}) {
    const std::string path = dir_ + name;
    try {
      LoadPhotometricFile(path);
      ADD_FAILURE() << "accepted " << path;
    } catch (const SceneError& e) {
      const std::string what = e.what();
      EXPECT_EQ(e.file(), path);
      EXPECT_NE(what.find("cannot read the photometric file"), std::string::npos) << what;
      EXPECT_NE(what.find("not a regular file"), std::string::npos) << what;
    }
  }
}

TEST_F(BoundedRead, IesTiltFileThatIsAFifo) {
  Write("t.ies", "IESNA:LM-63-2002\nTILT=pipe\n1 1000 1 3 1 1 2 0 0 0\n1 1 5\n0 45 90\n0\n10 5 0\n");
  try {
    LoadPhotometricFile(dir_ + "/t.ies");
    ADD_FAILURE() << "accepted";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.line(), 2) << what;
    EXPECT_NE(what.find("TILT=pipe: cannot read the tilt file: '" + fifo_ +
                        "' is a FIFO (named pipe), not a regular file"),
              std::string::npos)
        << what;
  }
}

TEST_F(BoundedRead, SceneMeshMtllibAndLidThatAreAFifoOrDevZero) {
  // The mesh: the scene's line of `file`, the path and why.
  std::string what = SceneErrorOf(Head() + "[[mesh]]\nfile = \"/dev/zero\"\nreflectance = 0.5\n");
  EXPECT_NE(what.find("s.toml:8:"), std::string::npos) << what;
  EXPECT_NE(what.find("cannot open OBJ file: '/dev/zero' is a character device"),
            std::string::npos)
      << what;
  what = SceneErrorOf(Head() + "[[mesh]]\nfile = \"pipe\"\nreflectance = 0.5\n");
  EXPECT_NE(what.find("'" + fifo_ + "' is a FIFO"), std::string::npos) << what;
  // An OBJ's mtllib: the OBJ's line.
  ASSERT_EQ(symlink(fifo_.c_str(), (dir_ + "/m.mtl").c_str()), 0);
  Write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  what = SceneErrorOf(Head() + "[[mesh]]\nfile = \"m.obj\"\n");
  EXPECT_NE(what.find("m.obj:1: cannot open material library: '" + dir_ + "/m.mtl' is a FIFO"),
            std::string::npos)
      << what;
  // An absolute mtllib path is taken as it is (not joined to the OBJ's folder).
  Write("z.obj", "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  what = SceneErrorOf(Head() + "[[mesh]]\nfile = \"z.obj\"\n");
  EXPECT_NE(what.find("z.obj:1: cannot open material library: '/dev/zero' is a character device"),
            std::string::npos)
      << what;
  // A luminaire's photometric file: the scene's line and the file's problem.
  what = SceneErrorOf(Head() +
                      "[[quad]]\nname = \"floor\"\ncorners = [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]\n"
                      "reflectance = 0.5\n[[luminaire]]\nname = \"a\"\nposition = [0.5, 0.5, 2]\n"
                      "mounting = \"hanging\"\nlid = { type = \"file\", path = \"/dev/zero\" }\n");
  EXPECT_NE(what.find("s.toml:15:"), std::string::npos) << what;
  EXPECT_NE(what.find("'/dev/zero' is a character device, not a regular file"), std::string::npos)
      << what;
  // The scene file itself.
  try {
    LoadScene(fifo_);
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open scene file: '" + fifo_ + "' is a FIFO"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace relight::baker
