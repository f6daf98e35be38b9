// Reading a file named by the user or by another input file (a scene, its
// OBJ meshes and their mtllib, photometric files, an IES TILT=<file>): only a
// regular file, and only up to a size limit, so /dev/zero, a FIFO or a
// directory is an error instead of a hang or an unbounded allocation
// (PITFALLS.md, "Fuzzing and sanitizers").
#pragma once

#include <cstdint>
#include <string>

namespace relight::baker {

// Limits, in bytes (docs/scene-format.md, docs/photometry.md). Far above any
// real input: the largest manufacturer's photometric file we know is ~200 KB,
// and an OBJ of 256 MiB already holds more patches than a bake allows.
inline constexpr std::uint64_t kMaxSceneFileBytes = 16ull << 20;         // scene TOML
inline constexpr std::uint64_t kMaxMeshFileBytes = 256ull << 20;         // OBJ
inline constexpr std::uint64_t kMaxMaterialFileBytes = 16ull << 20;      // MTL
inline constexpr std::uint64_t kMaxPhotometricFileBytes = 4ull << 20;    // IES, LDT, TILT file

// Reads all of `path` into *text. Refuses (returns false and sets *why to a
// reason naming the path, e.g. "'/dev/zero' is a character device, not a
// regular file") anything that is not a regular file or is larger than
// `max_bytes`; the file is opened without blocking and checked through the
// open descriptor, so a FIFO cannot stall it and a swap between the check
// and the read changes nothing.
bool ReadBoundedFile(const std::string& path, std::uint64_t max_bytes, std::string* text,
                     std::string* why);

}  // namespace relight::baker
