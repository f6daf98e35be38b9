// ValidateBake: every rule of bake_check.h over a whole Bake in memory, so
// WriteBake never writes a file ReadBake rejects and Engine::Open(Bake)
// takes exactly what ReadBake would (limits: relight/bake/bake_limits.h).
#include <string>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/bake/bake_check.h"

namespace relight {
namespace {

using namespace bake_format;  // NOLINT: the checks read better bare

Status Invalid(const std::string& where, const std::string& what) {
  return Status(StatusCode::kInvalidArgument, "bake: " + where + ": " + what);
}

std::string LuminaireLabel(size_t index, const BakeLuminaire& lum) {
  return StrFormat("luminaire %zu '%s'", index, lum.name.c_str());
}

std::string SetLabel(const Bake& bake, uint32_t set) {
  if (set == 0) return "receiver set 0 (vertices)";
  return StrFormat("receiver set %u (grid %u '%s')", set, set - 1,
                   bake.grids[set - 1].name.c_str());
}

}  // namespace

Status ValidateBake(const Bake& bake) {
  std::string e = CheckSceneHeader(bake);
  if (!e.empty()) return Invalid("scene", e);
  e = CheckMesh(bake.mesh);
  if (!e.empty()) return Invalid("mesh", e);
  e = CheckCounts(bake.mesh.vertex_count(), bake.mesh.triangle_count(),
                  bake.mesh.surface_names.size(), bake.grids.size(), bake.luminaires.size());
  if (!e.empty()) return Invalid("counts", e);
  std::vector<const std::string*> names;
  for (size_t g = 0; g < bake.grids.size(); ++g) {
    e = CheckGrid(bake.grids[g]);
    if (!e.empty()) return Invalid(StrFormat("grid %zu", g), e);
    names.push_back(&bake.grids[g].name);
  }
  e = CheckUniqueNames(names, "grid");
  if (!e.empty()) return Invalid("grids", e);
  names.clear();
  for (size_t l = 0; l < bake.luminaires.size(); ++l) {
    const BakeLuminaire& lum = bake.luminaires[l];
    const std::string label = LuminaireLabel(l, lum);
    e = CheckLuminaire(lum);
    if (!e.empty()) return Invalid(StrFormat("luminaire %zu", l), e);
    names.push_back(&lum.name);
    if (lum.receivers.size() != bake.receiver_set_count()) {
      return Invalid(label,
                     StrFormat("has %zu receiver sets, expected 1 + %zu grids = %u",
                               lum.receivers.size(), bake.grids.size(), bake.receiver_set_count()));
    }
    for (uint32_t s = 0; s < bake.receiver_set_count(); ++s) {
      const uint32_t count = bake.receiver_count(s);
      e = CheckDirect(lum.receivers[s], lum.direct_mode, count);
      const BakeLightReceivers& rec = lum.receivers[s];
      if (e.empty() && rec.compressed.present()) {
        e = rec.basis.empty() && rec.basis_scale.empty()
                ? CheckCompressedBasis(rec.compressed, lum.sh_degree, count)
                : "has both a basis and a compressed basis";
      } else if (e.empty()) {
        e = CheckBasis(rec, lum.sh_degree, count);
      }
      if (!e.empty()) return Invalid(label + ", " + SetLabel(bake, s), e);
    }
  }
  e = CheckUniqueNames(names, "luminaire");
  if (!e.empty()) return Invalid("luminaires", e);
  if (bake.hierarchy) {
    e = CheckHierarchyNodes(*bake.hierarchy, bake.mesh);
    if (!e.empty()) return Invalid("hierarchy nodes", e);
    e = CheckHierarchyLinks(*bake.hierarchy);
    if (!e.empty()) return Invalid("hierarchy links", e);
    uint64_t points = 0;
    for (const BakeGrid& grid : bake.grids) points += grid.point_count();
    e = CheckGridLinks(*bake.hierarchy, points);
    if (!e.empty()) return Invalid("hierarchy grid links", e);
  }
  return Status::Ok();
}


}  // namespace relight
