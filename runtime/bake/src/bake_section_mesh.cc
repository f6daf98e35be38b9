// Section MESH: positions, normals, albedo, triangles, their surfaces, surface names.
// Encoder and decoder side by side, field order as in docs/bake-format.md.
#include <string>
#include <utility>
#include <vector>

#include "bake_sections.h"
#include "relight/bake/bake_check.h"
#include "relight/base/sh_index.h"

namespace relight::bake_format {

void EncodeMesh(const BakeMesh& mesh, std::vector<uint8_t>* out) {
  ByteWriter w(out);
  w.PutPlanar(mesh.positions, 3);
  w.PutPlanar(mesh.normals, 3);
  w.PutPlanar(mesh.albedo, 3);
  w.PutPlanar(mesh.triangles, 3);
  w.PutPlanar(mesh.triangle_surface, 1);
  for (const std::string& name : mesh.surface_names) w.PutString(name);
}

Status DecodeMesh(ContainerReader* in, const Counts& counts, Bake* bake) {
  const std::string label = "section MESH";
  const Counts& c = counts;
  const uint64_t fixed = MeshBytesWithoutNames(c.vertices, c.triangles);
  RELIGHT_RETURN_IF_ERROR(in->Expect(1, kTagMesh, label, fixed + kStringBytes * c.surfaces,
                                 fixed + (kStringBytes + kMaxNameBytes) * c.surfaces));
  ByteReader r(nullptr, 0);
  RELIGHT_RETURN_IF_ERROR(in->Load(1, label, &r));
  BakeMesh& m = bake->mesh;
  const size_t v3 = 3 * size_t{c.vertices};
  r.GetPlanar(&m.positions, v3, 3, "positions");
  r.GetPlanar(&m.normals, v3, 3, "normals");
  r.GetPlanar(&m.albedo, v3, 3, "albedo");
  r.GetPlanar(&m.triangles, 3 * size_t{c.triangles}, 3, "triangles");
  r.GetPlanar(&m.triangle_surface, size_t{c.triangles}, 1, "triangle_surface");
  m.surface_names.resize(c.surfaces);
  for (std::string& name : m.surface_names) r.GetString(&name, kMaxNameBytes, "surface name");
  RELIGHT_RETURN_IF_ERROR(in->Finish(r, label));
  const std::string e = CheckMesh(m);
  if (!e.empty()) return in->Corrupt(label, e);
  return Status::Ok();
}

}  // namespace relight::bake_format
