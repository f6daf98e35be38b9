// The plain (non-libFuzzer) driver of a fuzz target: feeds every file named
// on the command line, or found under a folder named there, to
// LLVMFuzzerTestOneInput once. With GCC (no libFuzzer) each target builds
// with this main and ctest replays its corpus on every build, so the inputs
// that once crashed a reader stay regression tests.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

std::vector<uint8_t> ReadAll(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::filesystem::path> files;
  for (int i = 1; i < argc; ++i) {
    const std::filesystem::path arg(argv[i]);
    if (std::filesystem::is_directory(arg)) {
      for (const auto& entry : std::filesystem::recursive_directory_iterator(arg)) {
        if (entry.is_regular_file()) files.push_back(entry.path());
      }
    } else {
      files.push_back(arg);
    }
  }
  std::sort(files.begin(), files.end());  // the same order on every run
  if (files.empty()) {
    std::fprintf(stderr, "%s: no corpus files given\n", argv[0]);
    return 1;
  }
  for (const auto& path : files) {
    const std::vector<uint8_t> bytes = ReadAll(path);
    std::fprintf(stderr, "%s\n", path.c_str());  // the input a crash belongs to
    // Empty inputs are fed too (data may be null then: give a valid pointer).
    static const uint8_t kNothing = 0;
    LLVMFuzzerTestOneInput(bytes.empty() ? &kNothing : bytes.data(), bytes.size());
  }
  std::printf("%zu inputs, no crash\n", files.size());
  return 0;
}
