// Fuzz target: the bake's section decoders and validation. A mutated byte
// almost always breaks a crc, so bake_fuzz rarely gets past the table of
// contents; this target first re-seals the input as a writer would: every
// section's crc (when its bytes lie inside the input) and the header's crc
// are recomputed, then ParseBake and the engine run as in bake_fuzz. The
// seeds (corpus/bake_sections) store their sections uncompressed
// (tests/fuzz/unpack_bake.py), so mutations land in the decoders' bytes.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bake_bytes.h"
#include "bake_exercise.h"
#include "bake_format.h"
#include "relight/bake/bake.h"

namespace bf = relight::bake_format;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < bf::kHeaderBytes) return 0;
  std::vector<uint8_t> file(data, data + size);
  const uint32_t sections = bf::LoadLe<uint32_t>(file.data() + bf::kSectionCountOffset);
  if (sections > bf::kMaxSections || bf::kHeaderBytes + uint64_t{sections} * bf::kTocEntryBytes > size) return 0;
  for (uint32_t i = 0; i < sections; ++i) {
    uint8_t* entry_bytes = file.data() + bf::kHeaderBytes + size_t{i} * bf::kTocEntryBytes;
    bf::TocEntry e = bf::LoadTocEntry(entry_bytes);
    if (e.offset <= size && e.stored <= size - e.offset) {
      e.crc = bf::Crc32(file.data() + e.offset, static_cast<size_t>(e.stored));
      bf::StoreTocEntry(entry_bytes, e);
    }
  }
  const size_t toc_end = bf::kHeaderBytes + size_t{sections} * bf::kTocEntryBytes;
  uint32_t crc = bf::Crc32(file.data(), bf::kHeaderCrcOffset);
  crc = bf::Crc32(file.data() + bf::kHeaderBytes, toc_end - bf::kHeaderBytes, crc);
  bf::StoreLe(file.data() + bf::kHeaderCrcOffset, crc);

  relight::Bake bake;
  if (!relight::ParseBake(file.data(), file.size(), &bake).ok()) return 0;
  relight::fuzz::ExerciseBake(std::move(bake));
  return 0;
}
