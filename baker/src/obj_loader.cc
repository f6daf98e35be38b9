// Wavefront OBJ + MTL reader: the geometry and diffuse colours a scene mesh
// needs, nothing more (obj_loader.h lists what is read and what is ignored).
#include "obj_loader.h"

#include <charconv>
#include <cmath>
#include <set>
#include <sstream>

#include "bounded_read.h"
#include "polygon_check.h"

namespace relight::baker {

namespace {

std::string FolderOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// Whitespace-separated tokens of a line, without its # comment.
std::vector<std::string> Tokens(std::string line) {
  const size_t hash = line.find('#');
  if (hash != std::string::npos) line.resize(hash);
  std::vector<std::string> out;
  std::istringstream in(line);
  std::string token;
  while (in >> token) out.push_back(token);
  return out;
}

bool ParseDouble(const std::string& text, double* out) {
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, *out);
  return result.ec == std::errc() && result.ptr == end && std::isfinite(*out);
}

bool ParseLong(const std::string& text, long* out) {
  const char* end = text.data() + text.size();
  const auto result = std::from_chars(text.data(), end, *out);
  return result.ec == std::errc() && result.ptr == end;
}

// Lines of a file already read whole (bounded_read.h), split at '\n'.
class LineReader {
 public:
  LineReader(const std::string& text, std::string path) : path_(std::move(path)), text_(text) {}
  // Next line's tokens; false at the end of the file.
  bool Next(std::vector<std::string>* tokens) {
    if (pos_ >= text_.size()) return false;
    size_t end = text_.find('\n', pos_);
    if (end == std::string::npos) end = text_.size();
    ++line_;
    *tokens = Tokens(text_.substr(pos_, end - pos_));
    pos_ = end + 1;
    return true;
  }
  int line() const { return line_; }
  const std::string& path() const { return path_; }
  [[noreturn]] void Fail(const std::string& what) const { throw SceneError(path_, line_, what); }

 private:
  std::string path_;
  const std::string& text_;
  size_t pos_ = 0;
  int line_ = 0;
};

void LoadMtl(const std::string& path, const std::string& obj_path, int obj_line,
             std::map<std::string, Rgb>* materials) {
  std::string mtl_text, why;
  if (!ReadBoundedFile(path, kMaxMaterialFileBytes, &mtl_text, &why)) {
    throw SceneError(obj_path, obj_line, "cannot open material library: " + why);
  }
  LineReader reader(mtl_text, path);
  std::map<std::string, int> defined_at;  // this file's materials, line of newmtl
  std::set<std::string> with_kd;
  std::string current;
  std::vector<std::string> t;
  while (reader.Next(&t)) {
    if (t.empty()) continue;
    if (t[0] == "newmtl") {
      if (t.size() != 2) reader.Fail("newmtl needs exactly one name");
      current = t[1];
      if (materials->count(current) != 0) reader.Fail("material '" + current + "' defined twice");
      (*materials)[current] = Rgb{0, 0, 0};
      defined_at[current] = reader.line();
    } else if (t[0] == "Kd") {
      if (current.empty()) reader.Fail("Kd before any newmtl");
      // "Kd r" means grey; "Kd spectral ..." and "Kd xyz ..." are not supported.
      if (t.size() != 2 && t.size() != 4)
        reader.Fail("Kd must be followed by r g b (or one grey value)");
      Rgb kd{};
      for (size_t k = 0; k < 3; ++k) {
        const std::string& text = t[t.size() == 2 ? 1 : k + 1];
        if (!ParseDouble(text, &kd[k]) || kd[k] < 0.0 || kd[k] >= 1.0) {
          reader.Fail("Kd must be RGB reflectances in [0, 1) (1 would reflect all light), got '" +
                      text + "'");
        }
      }
      (*materials)[current] = kd;
      with_kd.insert(current);
    }
  }
  for (const auto& [name, line] : defined_at) {
    if (with_kd.count(name) == 0) {
      throw SceneError(path, line, "material '" + name + "' has no Kd (diffuse reflectance)");
    }
  }
}

// Resolves one corner "v", "v/vt", "v//vn" or "v/vt/vn" to a 0-based vertex index.
size_t CornerIndex(const LineReader& reader, const std::string& corner, size_t vertex_count,
                   size_t texcoord_count, size_t normal_count) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t slash = corner.find('/', start);
    parts.push_back(corner.substr(start, slash - start));
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  if (parts.size() > 3 || parts[0].empty()) {
    reader.Fail("face corner '" + corner + "' must be v, v/vt, v//vn or v/vt/vn");
  }
  const char* names[3] = {"vertex", "texture coordinate", "normal"};
  const char* plurals[3] = {"vertices", "texture coordinates", "normals"};
  const size_t counts[3] = {vertex_count, texcoord_count, normal_count};
  size_t resolved[3] = {0, 0, 0};
  for (size_t k = 0; k < parts.size(); ++k) {
    if (parts[k].empty()) continue;  // the vt of v//vn
    long index = 0;
    if (!ParseLong(parts[k], &index)) {
      reader.Fail("face corner '" + corner + "': '" + parts[k] + "' is not an integer index");
    }
    const long count = static_cast<long>(counts[k]);
    // 1-based; negative counts back from the last one defined so far.
    const long zero_based = index > 0 ? index - 1 : count + index;
    if (index == 0 || zero_based < 0 || zero_based >= count) {
      reader.Fail("face corner '" + corner + "': " + names[k] + " index " + parts[k] +
                  " is out of range (" + std::to_string(count) + " " +
                  (count == 1 ? names[k] : plurals[k]) + " defined so far; indices start at 1)");
    }
    resolved[k] = static_cast<size_t>(zero_based);
  }
  return resolved[0];
}

bool IsDegenerate(const std::vector<Vec3>& triangle) { return !PolygonProblem(triangle).empty(); }

double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Splits a polygon that is not a usable quad into triangles that keep its
// winding; drops zero-area pieces (collinear corners). Empty if impossible.
std::vector<std::vector<Vec3>> Triangulate(const std::vector<Vec3>& polygon) {
  const Vec3 normal = NewellNormal(polygon);
  const size_t n = polygon.size();
  // A quad may be concave: try both diagonals. Larger polygons: a fan from corner 0.
  const size_t first_apexes = n == 4 ? 2 : 1;
  for (size_t apex = 0; apex < first_apexes; ++apex) {
    std::vector<std::vector<Vec3>> triangles;
    bool consistent = true;
    for (size_t i = 1; i + 1 < n; ++i) {
      std::vector<Vec3> t{polygon[apex], polygon[(apex + i) % n], polygon[(apex + i + 1) % n]};
      if (IsDegenerate(t)) continue;
      if (Dot(NewellNormal(t), normal) <= 0.0) consistent = false;
      triangles.push_back(std::move(t));
    }
    if (consistent && !triangles.empty()) return triangles;
  }
  return {};
}

}  // namespace

ObjModel LoadObj(const std::string& path, bool read_materials) {
  std::string text, why;
  if (!ReadBoundedFile(path, kMaxMeshFileBytes, &text, &why)) {
    throw SceneError(path, 0, "cannot open OBJ file: " + why);
  }
  return ParseObj(text, path, read_materials);
}

ObjModel ParseObj(const std::string& text, const std::string& path, bool read_materials) {
  LineReader reader(text, path);
  ObjModel model;
  std::vector<Vec3> vertices;
  size_t texcoord_count = 0, normal_count = 0;
  std::string material;
  std::set<std::string> libraries;
  std::vector<std::string> t;
  while (reader.Next(&t)) {
    if (t.empty()) continue;
    const std::string& op = t[0];
    if (op == "v") {
      if (t.size() != 4 && t.size() != 5) reader.Fail("v must be followed by x y z [w]");
      Vec3 p{};
      for (size_t k = 0; k < 3; ++k) {
        if (!ParseDouble(t[k + 1], &p[k])) {
          reader.Fail("v coordinate '" + t[k + 1] + "' is not a finite number");
        }
      }
      vertices.push_back(p);
    } else if (op == "vt") {
      ++texcoord_count;
    } else if (op == "vn") {
      ++normal_count;
    } else if (op == "mtllib" && read_materials) {
      if (t.size() < 2) reader.Fail("mtllib needs a file name");
      for (size_t k = 1; k < t.size(); ++k) {
        // Relative to the OBJ's folder, as exporters write it; an absolute path as it is.
        const std::string library = t[k][0] == '/' ? t[k] : FolderOf(path) + t[k];
        // Some exporters repeat mtllib; read each library once.
        if (libraries.insert(library).second) {
          LoadMtl(library, path, reader.line(), &model.materials);
        }
      }
    } else if (op == "usemtl" && read_materials) {
      if (t.size() != 2) reader.Fail("usemtl needs exactly one material name");
      if (model.materials.count(t[1]) == 0) {
        reader.Fail("usemtl '" + t[1] + "': no such material in the mtllib files read so far");
      }
      material = t[1];
    } else if (op == "f") {
      if (t.size() < 4) reader.Fail("a face needs at least 3 corners");
      if (read_materials && material.empty()) {
        reader.Fail("face has no material: add usemtl before it, or give material in the scene");
      }
      std::vector<Vec3> polygon;
      for (size_t k = 1; k < t.size(); ++k) {
        polygon.push_back(
            vertices[CornerIndex(reader, t[k], vertices.size(), texcoord_count, normal_count)]);
      }
      const bool usable_quad = polygon.size() == 4 && PolygonProblem(polygon).empty();
      if (polygon.size() == 3 || (usable_quad && IsFlat(polygon))) {
        model.faces.push_back(ObjFace{polygon, material, reader.line()});
        continue;
      }
      const auto triangles = usable_quad ? SplitQuad(polygon) : Triangulate(polygon);
      if (triangles.empty()) {
        reader.Fail(
            "face is degenerate or self-intersecting (its corners must run around a "
            "simple outline)");
      }
      for (const auto& triangle : triangles) {
        model.faces.push_back(ObjFace{triangle, material, reader.line()});
      }
    }
  }
  if (model.faces.empty()) throw SceneError(path, 0, "OBJ file has no faces");
  return model;
}

}  // namespace relight::baker
