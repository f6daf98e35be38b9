// Section GRID: one calculation grid (name, shape, points, normals).
// Encoder and decoder side by side, field order as in docs/bake-format.md.
#include <string>
#include <utility>
#include <vector>

#include "bake_sections.h"
#include "relight/bake/bake_check.h"
#include "relight/base/sh_index.h"

namespace relight::bake_format {

void EncodeGrid(const BakeGrid& grid, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  w.PutString(grid.name);
  w.Put(grid.columns);
  w.Put(grid.rows);
  w.PutPlanar(grid.points, 3);
  w.PutPlanar(grid.normals, 3);
}

Status DecodeGrid(ContainerReader* in, const Counts& counts, uint32_t g, Bake* bake) {
  const std::string label = StrFormat("section GRID[%u]", g);
  const size_t index = 2 + g;
  const uint32_t points = counts.grid_points[g];
  RELIGHT_RETURN_IF_ERROR(
      in->Expect(index, kTagGrid, label, GridBytes(1, points), GridBytes(kMaxNameBytes, points)));
  ByteReader r(nullptr, 0);
  RELIGHT_RETURN_IF_ERROR(in->Load(index, label, &r));
  BakeGrid grid;
  r.GetString(&grid.name, kMaxNameBytes, "name");
  grid.columns = r.Get<uint32_t>("columns");
  grid.rows = r.Get<uint32_t>("rows");
  r.GetPlanar(&grid.points, 3 * size_t{points}, 3, "points");
  r.GetPlanar(&grid.normals, 3 * size_t{points}, 3, "normals");
  RELIGHT_RETURN_IF_ERROR(in->Finish(r, label));
  const std::string e = CheckGrid(grid);
  if (!e.empty()) return in->Corrupt(label, e);
  bake->grids.push_back(std::move(grid));
  return Status::Ok();
}

}  // namespace relight::bake_format
