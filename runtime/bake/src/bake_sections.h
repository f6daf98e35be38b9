// One encoder and one decoder per bake section (docs/bake-format.md, one
// table per section), each pair in its own file (bake_section_*.cc). An
// encoder appends a section's raw payload; a decoder expects, loads (through
// the container, bake_container.h), parses and checks (bake_check.h) it.
// Private to the bake layer.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "bake_container.h"
#include "relight/bake/bake.h"

namespace relight::bake_format {

// The counts META declares; every later section is sized from them.
struct Counts {
  uint32_t vertices = 0, triangles = 0, surfaces = 0, grids = 0, luminaires = 0;
  std::vector<uint32_t> grid_points;
};

void EncodeMeta(const Bake& bake, std::vector<uint8_t>* out);
Status DecodeMeta(ContainerReader* in, Counts* counts, Bake* bake);

void EncodeMesh(const BakeMesh& mesh, std::vector<uint8_t>* out);
Status DecodeMesh(ContainerReader* in, const Counts& counts, Bake* bake);

void EncodeGrid(const BakeGrid& grid, std::vector<uint8_t>* out);
// Appends grid g to bake->grids.
Status DecodeGrid(ContainerReader* in, const Counts& counts, uint32_t g, Bake* bake);

// `version`: the file's; from 4 on the LUMI ends with the zoom tail.
void EncodeLuminaire(const BakeLuminaire& lum, uint32_t version, std::vector<uint8_t>* out);
// Appends luminaire l (without receivers) to bake->luminaires.
Status DecodeLuminaire(ContainerReader* in, const Counts& counts, uint32_t l, Bake* bake);

// LUMI's version 4 tail (bake_lumi_zoom.cc): the profile count, then, if
// not 0, the zoom's angles, lumens and profile. Checks counts before allocating.
void EncodeLuminaireZoom(const BakeZoom& zoom, ByteWriter* w);
Status DecodeLuminaireZoom(ContainerReader* in, const std::string& label, ByteReader* r,
                           BakeZoom* zoom);

void EncodeDirect(const BakeLightReceivers& rec, std::vector<uint8_t>* out);
Status DecodeDirect(ContainerReader* in, size_t index, const std::string& label, DirectMode mode,
                    uint32_t count, BakeLightReceivers* rec);
void EncodeBasis(const BakeLightReceivers& rec, std::vector<uint8_t>* out);
Status DecodeBasis(ContainerReader* in, size_t index, const std::string& label, int degree,
                   uint32_t count, BakeLightReceivers* rec);

// CPCA (bake_section_compressed.cc): a compressed basis in place of BASE.
void EncodeCompressedBasis(const BakeCompressedBasis& cpca, std::vector<uint8_t>* out);
Status DecodeCompressedBasis(ContainerReader* in, size_t index, const std::string& label, int degree,
                             uint32_t count, uint8_t weight_bits, BakeLightReceivers* rec);

void EncodeHierarchyNodes(const BakeHierarchy& h, std::vector<uint8_t>* out);
void EncodeHierarchyLinks(const BakeHierarchy& h, std::vector<uint8_t>* out);
// HIER at `index`, LINK after it; sets bake->hierarchy.
Status DecodeHierarchy(ContainerReader* in, size_t index, Bake* bake);
// GLNK (bake_section_grid_links.cc), after LINK: sets the hierarchy's grid links.
void EncodeGridLinks(const BakeHierarchy& h, std::vector<uint8_t>* out);
Status DecodeGridLinks(ContainerReader* in, size_t index, uint32_t grid_points, Bake* bake);

}  // namespace relight::bake_format
