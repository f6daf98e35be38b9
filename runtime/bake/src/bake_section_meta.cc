// Section META: scene name, white, camera, and the counts every later section is sized from.
// Encoder and decoder side by side, field order as in docs/bake-format.md.
#include <string>
#include <utility>
#include <vector>

#include "bake_sections.h"
#include "relight/bake/bake_check.h"
#include "relight/base/sh_index.h"

namespace relight::bake_format {

void EncodeMeta(const Bake& bake, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  w.PutString(bake.scene_name);
  w.Put(bake.white_luminance);
  for (int32_t v : bake.camera.position) w.Put(v);
  for (int32_t v : bake.camera.target) w.Put(v);
  w.Put(bake.camera.fov_y);
  w.Put(bake.mesh.vertex_count());
  w.Put(bake.mesh.triangle_count());
  w.Put(static_cast<uint32_t>(bake.mesh.surface_names.size()));
  w.Put(static_cast<uint32_t>(bake.grids.size()));
  w.Put(static_cast<uint32_t>(bake.luminaires.size()));
  for (const BakeGrid& g : bake.grids) w.Put(g.point_count());
}

Status DecodeMeta(ContainerReader* in, Counts* counts, Bake* bake) {
  const std::string label = "section META";
  RELIGHT_RETURN_IF_ERROR(in->Expect(0, kTagMeta, label, MetaBytes(0, 0), kMaxMetaBytes));
  ByteReader r(nullptr, 0);
  RELIGHT_RETURN_IF_ERROR(in->Load(0, label, &r));
  r.GetString(&bake->scene_name, kMaxNameBytes, "scene name");
  bake->white_luminance = r.Get<int32_t>("white luminance");
  for (int32_t& v : bake->camera.position) v = r.Get<int32_t>("camera position");
  for (int32_t& v : bake->camera.target) v = r.Get<int32_t>("camera target");
  bake->camera.fov_y = r.Get<int32_t>("camera fov_y");
  Counts& c = *counts;
  c.vertices = r.Get<uint32_t>("vertex count");
  c.triangles = r.Get<uint32_t>("triangle count");
  c.surfaces = r.Get<uint32_t>("surface count");
  c.grids = r.Get<uint32_t>("grid count");
  c.luminaires = r.Get<uint32_t>("luminaire count");
  if (r.failed()) return in->Finish(r, label);
  std::string e = CheckCounts(c.vertices, c.triangles, c.surfaces, c.grids, c.luminaires);
  if (!e.empty()) return in->Corrupt(label, e);
  c.grid_points.resize(c.grids);
  for (uint32_t g = 0; g < c.grids; ++g) {
    c.grid_points[g] = r.Get<uint32_t>("grid point count");
    e = CheckGridPointCount(c.grid_points[g]);
    if (!e.empty()) return in->Corrupt(label, StrFormat("grid %u: %s", g, e.c_str()));
  }
  RELIGHT_RETURN_IF_ERROR(in->Finish(r, label));
  e = CheckSceneHeader(*bake);
  if (!e.empty()) return in->Corrupt(label, e);
  return Status::Ok();
}

}  // namespace relight::bake_format
