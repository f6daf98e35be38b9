// The consistency rules of a Bake, shared by WriteBake (which reports a
// broken rule as kInvalidArgument) and the reader (kCorrupt), so a file the
// writer accepts is exactly a file the reader accepts.
//
// Each check returns "" when the part is consistent, otherwise what is wrong
// and where inside the part ("triangle 5: vertex index 12 >= vertex count 10");
// the caller prefixes the part ("section MESH: ", "bake: mesh: ").
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "relight/bake/bake.h"

namespace relight::bake_format {

// "what has N values, expected how = M".
std::string CountMismatch(const char* what, size_t have, const char* expected_how,
                          uint64_t expected);
// Up to kMaxNameBytes of UTF-8 without control characters; empty only if allowed.
std::string CheckName(const std::string& name, bool allow_empty);
// Mantissa in [2^29, 2^30) with a bounded exponent, or the zero scale {0, 0}.
std::string CheckScale(QuantScale scale);

// Counts against the plausibility limits of bake_format.h.
std::string CheckCounts(uint64_t vertices, uint64_t triangles, uint64_t surfaces, uint64_t grids,
                        uint64_t luminaires);
std::string CheckGridPointCount(uint64_t points);

// Scene name, white luminance and camera.
std::string CheckSceneHeader(const Bake& bake);
std::string CheckMesh(const BakeMesh& mesh);
std::string CheckGrid(const BakeGrid& grid);
// Everything but the receivers: name, enums, degree, defaults, LID.
std::string CheckLuminaire(const BakeLuminaire& lum);
// A luminaire's zoom (bake_check_zoom.cc): absent, or angles, lumens and profile in range.
std::string CheckZoom(const BakeZoom& zoom, const BakeLid& lid);
// A LID's (C, gamma) table and SH coefficients (empty for an axisymmetric one).
std::string CheckLidTable(const BakeLid& lid, int sh_degree);
// The exact direct term of one luminaire on one receiver set of `receivers` points.
std::string CheckDirect(const BakeLightReceivers& rec, DirectMode mode, uint32_t receivers);
// The SH basis of one luminaire on one receiver set.
std::string CheckBasis(const BakeLightReceivers& rec, int sh_degree, uint32_t receivers);
// The hierarchy's nodes against the mesh: array lengths, surface order, tree
// structure (roots, parents, contiguous breadth-first children), corners,
// areas, and leaves that cover every triangle exactly once.
std::string CheckHierarchyNodes(const BakeHierarchy& h, const BakeMesh& mesh);
// Its links against nodes that passed CheckHierarchyNodes: lengths, node
// indices, order, surfaces, factors and gradients.
std::string CheckHierarchyLinks(const BakeHierarchy& h);
// Its grid links (bake_check_grid_links.cc), none or one range per grid
// point: offsets, node indices ascending per point, factor sums at most 2.
std::string CheckGridLinks(const BakeHierarchy& h, uint64_t grid_points);
// A compressed basis (bake_check_compressed.cc): counts, cluster starts,
// scales, zero-scale rows and weight range, for `receivers` points.
std::string CheckCompressedBasis(const BakeCompressedBasis& cpca, int sh_degree, uint32_t receivers);
// Names must tell luminaires (and grids) apart: "" or the first duplicate.
std::string CheckUniqueNames(const std::vector<const std::string*>& names, const char* kind);

}  // namespace relight::bake_format
