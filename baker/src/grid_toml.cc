// A scene's [[grid]] table (docs/scene-format.md) into a CalcGrid: a
// rectangle (origin, u, v, columns, rows) or a list of points, with one
// normal. Errors name file:line through TomlFields.
#include "grid_toml.h"

#include <cstdint>
#include <optional>

#include "scene_geometry.h"
#include "vec3_math.h"

namespace relight::baker {
namespace {

constexpr int64_t kMaxGridPoints = 1000000;

}  // namespace

CalcGrid ReadGrid(const toml::table& table, const std::string& path,
                  std::map<std::string, int>* grid_lines) {
  TomlFields f(table, path, "grid");
  f.NameFrom("name", "grid");
  f.CheckKeys({"name", "origin", "u", "v", "columns", "rows", "normal", "points"});
  CalcGrid grid;
  grid.name = f.Identifier("name");
  f.set_what("grid " + Quoted(grid.name));
  const auto [it, inserted] = grid_lines->emplace(grid.name, f.line());
  if (!inserted) {
    f.Fail(f.Required("name"),
           "name already used by the grid at line " + std::to_string(it->second));
  }
  std::optional<Vec3> normal;
  if (f.Has("normal")) {
    const Vec3 n = f.Vector("normal");
    if (Length(n) < kMinVectorM) f.Fail(f.Required("normal"), "normal must not be zero");
    normal = Scale(n, 1.0 / Length(n));
  }
  if (f.Has("points")) {
    for (const char* key : {"origin", "u", "v", "columns", "rows"}) {
      if (f.Has(key)) {
        f.Fail(f.Required(key),
               std::string("a grid has either points or a rectangle (origin, u, v, "
                           "columns, rows), not both; remove ") +
                   key);
      }
    }
    if (!normal) f.Fail("missing key 'normal' (a grid of points needs one)");
    const toml::array& points = f.Array("points");
    if (points.empty() || static_cast<int64_t>(points.size()) > kMaxGridPoints) {
      f.Fail(f.Required("points"), "points must hold 1.." + std::to_string(kMaxGridPoints) +
                                       " points, got " + Describe(f.Required("points")));
    }
    for (size_t i = 0; i < points.size(); ++i) {
      grid.points.push_back(f.ReadVec3(*points.get(i), "point " + std::to_string(i + 1)));
    }
  } else {
    const Vec3 origin = f.Vector("origin"), u = f.Vector("u"), v = f.Vector("v");
    const int64_t columns = f.Integer("columns", 1, kMaxGridPoints);
    const int64_t rows = f.Integer("rows", 1, kMaxGridPoints);
    if (columns * rows > kMaxGridPoints) {
      f.Fail(f.Required("rows"), "columns x rows must be at most " +
                                     std::to_string(kMaxGridPoints) + ", got " +
                                     std::to_string(columns * rows));
    }
    if (Length(u) < kMinVectorM) f.Fail(f.Required("u"), "u must not be zero");
    if (Length(v) < kMinVectorM) f.Fail(f.Required("v"), "v must not be zero");
    const Vec3 uv = Cross(u, v);
    if (Length(uv) < 1e-6 * Length(u) * Length(v)) {
      f.Fail(f.Required("v"), "u and v must not be parallel");
    }
    if (!normal) normal = Scale(uv, 1.0 / Length(uv));
    grid.columns = static_cast<int>(columns);
    grid.rows = static_cast<int>(rows);
    grid.points = RectangleGridPoints(origin, u, v, grid.columns, grid.rows);
  }
  grid.normals.assign(grid.points.size(), *normal);
  return grid;
}

}  // namespace relight::baker
