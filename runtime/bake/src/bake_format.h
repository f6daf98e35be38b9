// On-disk layout of a bake file, format version 7: the constants the writer
// and the reader share. docs/bake-format.md is the specification; keep the
// two in step. Private to the runtime.
#pragma once

#include <cstddef>
#include <cstdint>

#include "bake_bytes.h"
#include "relight/bake/bake.h"
#include "relight/bake/bake_limits.h"
#include "relight/base/sh_index.h"

namespace relight::bake_format {

// --- File header (28 bytes) and table of contents (36 bytes per section).
inline constexpr uint8_t kMagic[8] = {'R', 'E', 'L', 'I', 'G', 'H', 'T', '\0'};
inline constexpr uint32_t kVersion = 8;
// Version 1 files still read: their LUMI sections end after the LID samples
// (no orientation, ranges or (C, gamma) table; defaults apply).
inline constexpr uint32_t kOldestVersion = 1;
// The writer stamps the lowest version that holds the bake: 2 without a
// hierarchy, so readers that predate HIER and LINK still read those files.
inline constexpr uint32_t kVersionWithoutHierarchy = 2;
inline constexpr uint32_t kFirstVersionWithHierarchy = 3;
// Version 4: every LUMI ends with the zoom tail (its profile count 0 when the
// luminaire has no zoom). Written only when some luminaire zooms.
inline constexpr uint32_t kFirstVersionWithZoom = 4;
// Version 5: a CPCA section (compressed basis) may stand where a BASE does.
// Written only when some basis is compressed.
inline constexpr uint32_t kFirstVersionWithCompressed = 5;
// Version 6: a GLNK section (links from the nodes to the grid points) may
// follow LINK. Written only when the hierarchy has them.
inline constexpr uint32_t kFirstVersionWithGridLinks = 6;
// Version 7: a luminaire's SH degree may exceed 16 (up to kMaxShDegree, 22:
// narrow zooms, issue 12). Nothing else changed, so the writer stamps it only
// when some degree does; a version 6 reader then stops at the version, not at
// a degree it would call corrupt.
inline constexpr uint32_t kFirstVersionWithHighDegree = 7;
inline constexpr int kMaxShDegreeBeforeVersion7 = 16;
// Version 8: a CPC8 section (a compressed basis with 8-bit weights) may stand
// where a CPCA does. Written only when some basis has them.
inline constexpr uint32_t kFirstVersionWith8BitWeights = 8;
inline constexpr size_t kVersionOffset = 8;
inline constexpr size_t kSectionCountOffset = 12;
inline constexpr size_t kFileSizeOffset = 16;
inline constexpr size_t kHeaderCrcOffset = 24;  // crc32 of bytes [0, 24) then of the TOC
inline constexpr size_t kHeaderBytes = 28;
inline constexpr size_t kTocEntryBytes = 36;  // tag, flags, offset, stored, raw, crc
inline constexpr uint32_t kFlagZstd = 1u;     // bit 0: stored bytes are one zstd frame
inline constexpr uint32_t kKnownFlags = kFlagZstd;
inline constexpr int kZstdLevel = 6;
inline constexpr int kZstdWorkers = 2;

// A fourcc reads as its four ASCII letters in file order.
constexpr uint32_t Fourcc(char a, char b, char c, char d) {
  return static_cast<uint32_t>(static_cast<uint8_t>(a)) |
         static_cast<uint32_t>(static_cast<uint8_t>(b)) << 8 |
         static_cast<uint32_t>(static_cast<uint8_t>(c)) << 16 |
         static_cast<uint32_t>(static_cast<uint8_t>(d)) << 24;
}
inline constexpr uint32_t kTagMeta = Fourcc('M', 'E', 'T', 'A');
inline constexpr uint32_t kTagMesh = Fourcc('M', 'E', 'S', 'H');
inline constexpr uint32_t kTagGrid = Fourcc('G', 'R', 'I', 'D');
inline constexpr uint32_t kTagLumi = Fourcc('L', 'U', 'M', 'I');
inline constexpr uint32_t kTagDirect = Fourcc('D', 'I', 'R', 'T');
inline constexpr uint32_t kTagBasis = Fourcc('B', 'A', 'S', 'E');
inline constexpr uint32_t kTagHierarchy = Fourcc('H', 'I', 'E', 'R');
inline constexpr uint32_t kTagLinks = Fourcc('L', 'I', 'N', 'K');
inline constexpr uint32_t kTagCompressed = Fourcc('C', 'P', 'C', 'A');
inline constexpr uint32_t kTagCompressed8 = Fourcc('C', 'P', 'C', '8');
inline constexpr uint32_t kTagGridLinks = Fourcc('G', 'L', 'N', 'K');

struct TocEntry {
  uint32_t tag = 0, flags = 0;
  uint64_t offset = 0, stored = 0, raw = 0;
  uint32_t crc = 0;
};

inline void StoreTocEntry(uint8_t* p, const TocEntry& e) {
  StoreLe(p, e.tag);
  StoreLe(p + 4, e.flags);
  StoreLe(p + 8, e.offset);
  StoreLe(p + 16, e.stored);
  StoreLe(p + 24, e.raw);
  StoreLe(p + 32, e.crc);
}

inline TocEntry LoadTocEntry(const uint8_t* p) {
  TocEntry e;
  e.tag = LoadLe<uint32_t>(p);
  e.flags = LoadLe<uint32_t>(p + 4);
  e.offset = LoadLe<uint64_t>(p + 8);
  e.stored = LoadLe<uint64_t>(p + 16);
  e.raw = LoadLe<uint64_t>(p + 24);
  e.crc = LoadLe<uint32_t>(p + 32);
  return e;
}

// --- Plausibility limits: relight/bake/bake_limits.h.
// zstd emits at best one 4-byte RLE block per 128 KiB (ratio 32768); twice
// that is a safe bound on what an honest frame can expand to.
inline constexpr uint64_t kMaxZstdExpansion = 65536;
inline constexpr uint32_t kMaxSections =
    2 + kMaxGrids + kMaxLuminaires * (1 + 2 * (1 + kMaxGrids)) + 3;

// --- Payload sizes in bytes (docs/bake-format.md, one table per section).
inline constexpr uint64_t kStringBytes = 4;  // u32 length; the bytes follow
inline constexpr uint64_t kMetaFixedBytes = 4 + 7 * 4 + 5 * 4;
inline constexpr uint64_t kMeshBytesPerVertex = 3 * 4 + 3 * 2 + 3 * 2;
inline constexpr uint64_t kMeshBytesPerTriangle = 3 * 4 + 4;
inline constexpr uint64_t kGridFixedBytes = 2 * 4;
inline constexpr uint64_t kGridBytesPerPoint = 3 * 4 + 3 * 2;
inline constexpr uint64_t kLumiFixedBytes = 3 * 4 + 4 * 1 + 2 * 4 + 4 * 2 + 4;
// Version 2 tail: yaw, roll, pan and tilt range, plane and gamma counts, SH count.
inline constexpr uint64_t kLumiTailFixedBytes = 4 * 4 + 2 * 4 + 4;
// Version 4 tail: profile count; then min, max, default, lumens, profile end.
inline constexpr uint64_t kLumiZoomFixedBytes = 4 + 3 * 4 + 8 + 4;
inline constexpr uint64_t kMaxLumiZoomBytes = kLumiZoomFixedBytes + 4 * uint64_t{kMaxZoomProfileSamples};
inline constexpr uint64_t kScaleBytes = 8;  // i32 mantissa, i32 exponent
inline constexpr uint64_t kDirectBytesPerReceiver = 3 * 2 + 4;
inline constexpr uint64_t kBasisBytesPerValue = 2;

constexpr uint64_t MetaBytes(uint64_t name_bytes, uint64_t grids) {
  return kStringBytes + name_bytes + kMetaFixedBytes + 4 * grids;
}
inline constexpr uint64_t kMaxMetaBytes = MetaBytes(kMaxNameBytes, kMaxGrids);
constexpr uint64_t MeshBytesWithoutNames(uint64_t vertices, uint64_t triangles) {
  return kMeshBytesPerVertex * vertices + kMeshBytesPerTriangle * triangles;
}
constexpr uint64_t GridBytes(uint64_t name_bytes, uint64_t points) {
  return kStringBytes + name_bytes + kGridFixedBytes + kGridBytesPerPoint * points;
}
constexpr uint64_t LumiBytes(uint64_t name_bytes, uint64_t lid_samples) {
  return kStringBytes + name_bytes + kLumiFixedBytes + 8 * lid_samples;
}
constexpr uint64_t LumiTailBytes(uint64_t planes, uint64_t gammas, uint64_t sh_terms) {
  return kLumiTailFixedBytes + 4 * (planes + gammas) + 8 * planes * gammas + 8 * sh_terms;
}
inline constexpr uint64_t kMaxLumiTailBytes =
    kLumiTailFixedBytes + 4 * (kMaxLidPlanes + kMaxLidGammas) + 8 * kMaxLidTableValues +
    8 * static_cast<uint64_t>(ShTermCount(kMaxShDegree));
constexpr uint64_t DirectBytes(uint64_t receivers) {
  return kScaleBytes + kDirectBytesPerReceiver * receivers;
}
constexpr uint64_t BasisBytes(uint64_t terms, uint64_t receivers) {
  return kScaleBytes * 3 * terms + kBasisBytesPerValue * 3 * terms * receivers;
}
// CPCA: cluster count C, component count r, C + 1 cluster starts, the 3T
// vector scales, the 3T x C(r+1) vector values, the receivers x r weights.
// C (r + 1) is at most receivers + kMaxCompressedComponents + 1 (a
// compressed basis is never much larger than the basis it replaces), which
// bounds the section before its counts are read. CPC8 is the same with a
// byte a weight (weight_bytes 1).
inline constexpr uint64_t kCompressedFixedBytes = 2 * 4;
constexpr uint64_t CompressedBytes(uint64_t terms, uint64_t receivers, uint64_t clusters,
                                   uint64_t components, uint64_t weight_bytes = 2) {
  return kCompressedFixedBytes + 4 * (clusters + 1) + kScaleBytes * 3 * terms +
         2 * 3 * terms * clusters * (components + 1) + weight_bytes * receivers * components;
}
constexpr uint64_t MaxCompressedVectors(uint64_t receivers) {
  return receivers + kMaxCompressedComponents + 1;
}
constexpr uint64_t MaxCompressedBytes(uint64_t terms, uint64_t receivers) {
  return kCompressedFixedBytes + 4 * (receivers + 1) + kScaleBytes * 3 * terms +
         2 * 3 * terms * MaxCompressedVectors(receivers) + 2 * receivers * kMaxCompressedComponents;
}
// HIER: count, then surface, parent, first child, child count, corner count,
// corners, area, leaf triangle per node. LINK: count, then p, q, f_pq, f_qp,
// g_pq, g_qp per link.
inline constexpr uint64_t kCountBytes = 4;
inline constexpr uint64_t kHierBytesPerNode = 2 + 4 + 4 + 1 + 1 + 4 * kBakeMaxNodeCorners + 8 + 4;
inline constexpr uint64_t kLinkBytesPerLink = 4 * 4 + 4 * 4;
constexpr uint64_t HierBytes(uint64_t nodes) { return kCountBytes + kHierBytesPerNode * nodes; }
constexpr uint64_t LinkBytes(uint64_t links) { return kCountBytes + kLinkBytesPerLink * links; }
// GLNK: point count P, link count K, then offsets u32[P + 1], node u32[K], f u32[K].
constexpr uint64_t GridLinkBytes(uint64_t points, uint64_t links) {
  return 2 * kCountBytes + 4 * (points + 1) + 8 * links;
}

}  // namespace relight::bake_format
