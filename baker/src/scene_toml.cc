// LoadScene: the scene TOML (docs/scene-format.md) into a Scene. Every
// object is read through TomlFields, so every error names file:line, the
// object and what was expected; unknown keys are errors.
#include <toml++/toml.h>

#include <algorithm>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <utility>

#include "bounded_read.h"
#include "grid_toml.h"
#include "luminaire_toml.h"
#include "obj_loader.h"
#include "polygon_check.h"
#include "relight/baker/photometry.h"
#include "relight/baker/scene.h"
#include "scene_geometry.h"
#include "toml_fields.h"
#include "vec3_math.h"

namespace relight::baker {

namespace {


std::string FolderOf(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

class SceneReader {
 public:
  SceneReader(const toml::table& root, std::string path)
      : root_(root, path, ""), path_(std::move(path)) {}

  Scene Read() {
    root_.CheckKeys(
        {"scene", "camera", "material", "quad", "triangle", "box", "mesh", "luminaire", "grid"});
    Scene scene;
    scene.path = path_;
    ReadSceneTable(&scene);
    ReadCamera(&scene.camera);
    for (const toml::table* t : TablesOf("material")) ReadMaterial(*t);
    for (const toml::table* t : TablesOf("quad")) ReadPolygon(*t, "quad", 4);
    for (const toml::table* t : TablesOf("triangle")) ReadPolygon(*t, "triangle", 3);
    for (const toml::table* t : TablesOf("box")) ReadBox(*t);
    for (const toml::table* t : TablesOf("mesh")) ReadMesh(*t);
    if (surfaces_.empty()) {
      throw SceneError(path_, 0,
                       "the scene has no surfaces (add [[quad]], [[triangle]], "
                       "[[box]] or [[mesh]])");
    }
    // File order, so surface indices follow the text (each object's faces stay together).
    std::stable_sort(surfaces_.begin(), surfaces_.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (auto& entry : surfaces_) {
      entry.second.line = entry.first;
      scene.surfaces.push_back(std::move(entry.second));
    }
    for (const toml::table* t : TablesOf("luminaire")) {
      scene.luminaires.push_back(ReadLuminaire(*t, path_, &luminaire_lines_));
    }
    for (const toml::table* t : TablesOf("grid")) {
      scene.grids.push_back(ReadGrid(*t, path_, &grid_lines_));
    }
    return scene;
  }

 private:
  // The tables of a [[key]] array; absent is empty.
  std::vector<const toml::table*> TablesOf(const char* key) const {
    std::vector<const toml::table*> out;
    const toml::node* node = root_.table().get(key);
    if (node == nullptr) return out;
    const auto* array = node->as_array();
    if (array == nullptr) {
      root_.Fail(*node, Quoted(key) + " must be written [[" + key + "]] (an array of tables)");
    }
    for (const toml::node& element : *array) {
      const auto* t = element.as_table();
      if (t == nullptr) {
        root_.Fail(element, "each " + Quoted(key) + " must be a table, got " + Describe(element));
      }
      out.push_back(t);
    }
    return out;
  }

  const toml::table& RequiredTable(const char* key) const {
    const toml::node* node = root_.table().get(key);
    if (node == nullptr) {
      throw SceneError(path_, 0, "missing table [" + std::string(key) + "]");
    }
    const auto* t = node->as_table();
    if (t == nullptr) root_.Fail(*node, "[" + std::string(key) + "] must be a table");
    return *t;
  }

  void ReadSceneTable(Scene* scene) const {
    TomlFields f(RequiredTable("scene"), path_, "[scene]");
    f.CheckKeys({"name", "patch_size", "white"});
    scene->name = f.String("name");
    if (scene->name.empty()) f.Fail(f.Required("name"), "name must not be empty");
    scene->patch_size_m = f.Number("patch_size", Positive(), 0.25);
    scene->white_cd_m2 = f.Number("white", NonNegative(), 0.0);
  }

  void ReadCamera(Camera* camera) const {
    TomlFields f(RequiredTable("camera"), path_, "[camera]");
    f.CheckKeys({"position", "target", "fov"});
    camera->position = f.Vector("position");
    camera->target = f.Vector("target");
    camera->fov_y_deg = f.Number("fov", Range{0, 180, true, true});
    if (Length(Sub(camera->target, camera->position)) < kMinVectorM) {
      f.Fail(f.Required("target"), "target must differ from position");
    }
  }

  // A reflectance: one grey number or [r, g, b], each in [0, 1) (1 would
  // reflect all light: no energy would ever leave the scene).
  Rgb ReadReflectance(const TomlFields& f, const toml::node& node, const std::string& name) const {
    const Range range = HalfOpen(0.0, 1.0);
    if (const auto* array = node.as_array()) {
      if (array->size() != 3) {
        f.Fail(node, name + " must be [r, g, b] or one grey number, got " + Describe(node));
      }
      Rgb rgb{};
      for (size_t k = 0; k < 3; ++k) rgb[k] = f.ReadNumber(*array->get(k), name, range);
      return rgb;
    }
    const double grey = f.ReadNumber(node, name, range);
    return Rgb{grey, grey, grey};
  }

  // A surface's colour: material = "name" or reflectance = ..., exactly one.
  Rgb ReadColour(const TomlFields& f) const {
    const bool has_material = f.Has("material"), has_reflectance = f.Has("reflectance");
    if (has_material && has_reflectance) {
      f.Fail(f.Required("reflectance"), "give either material or reflectance, not both");
    }
    if (has_reflectance) return ReadReflectance(f, f.Required("reflectance"), "reflectance");
    if (!has_material) f.Fail("missing key 'material' (or 'reflectance')");
    return LookUpMaterial(f, f.Required("material"));
  }

  Rgb LookUpMaterial(const TomlFields& f, const toml::node& node) const {
    const auto* s = node.as_string();
    if (s == nullptr) f.Fail(node, "material must be a material name, got " + Describe(node));
    const auto it = materials_.find(s->get());
    if (it == materials_.end()) {
      std::string known;
      for (const auto& entry : materials_) known += (known.empty() ? "" : ", ") + entry.first;
      f.Fail(node, "unknown material " + Quoted(s->get()) +
                       " (defined: " + (known.empty() ? "none" : known) + ")");
    }
    return it->second;
  }

  // Object names share one namespace so picking can tell surfaces apart.
  std::string ReadObjectName(TomlFields* f, const std::string& kind) {
    const std::string name = f->Identifier("name");
    f->set_what(kind + " " + Quoted(name));
    const auto [it, inserted] = object_lines_.emplace(name, f->line());
    if (!inserted) {
      f->Fail(f->Required("name"),
              "name already used by the object at line " + std::to_string(it->second));
    }
    return name;
  }

  void ReadMaterial(const toml::table& table) {
    TomlFields f(table, path_, "material");
    f.NameFrom("name", "material");
    f.CheckKeys({"name", "reflectance"});
    const std::string name = f.Identifier("name");
    f.set_what("material " + Quoted(name));
    if (materials_.count(name) != 0) f.Fail(f.Required("name"), "material defined twice");
    materials_[name] = ReadReflectance(f, f.Required("reflectance"), "reflectance");
  }

  void AddSurface(const TomlFields& f, int line, Surface surface, const toml::node& at) {
    const std::string problem = PolygonProblem(surface.corners);
    if (!problem.empty()) f.Fail(at, problem);
    // Within tolerance but warped (the Cornell box's left wall, by 0.8 mm):
    // onto the mean plane, so the mesher sees an exact plane.
    if (!IsFlat(surface.corners)) surface.corners = ProjectToMeanPlane(surface.corners);
    surfaces_.emplace_back(line, std::move(surface));
  }

  void ReadPolygon(const toml::table& table, const std::string& kind, size_t corner_count) {
    TomlFields f(table, path_, kind);
    f.NameFrom("name", kind);
    f.CheckKeys({"name", "corners", "material", "reflectance"});
    Surface surface;
    surface.name = ReadObjectName(&f, kind);
    const toml::array& corners = f.Array("corners");
    if (corners.size() != corner_count) {
      f.Fail(f.Required("corners"), "corners must be " + std::to_string(corner_count) +
                                        " points [x, y, z], got " +
                                        Describe(f.Required("corners")));
    }
    for (size_t i = 0; i < corner_count; ++i) {
      surface.corners.push_back(f.ReadVec3(*corners.get(i), "corner " + std::to_string(i + 1)));
    }
    surface.reflectance = ReadColour(f);
    AddSurface(f, f.line(), std::move(surface), f.Required("corners"));
  }

  void ReadBox(const toml::table& table) {
    TomlFields f(table, path_, "box");
    f.NameFrom("name", "box");
    f.CheckKeys(
        {"name", "min", "max", "rotate_z", "inward", "omit", "material", "reflectance", "faces"});
    const std::string name = ReadObjectName(&f, "box");
    const Vec3 min = f.Vector("min"), max = f.Vector("max");
    for (int k = 0; k < 3; ++k) {
      if (!(max[k] - min[k] >= kMinEdgeM)) {
        f.Fail(f.Required("max"), std::string("max must exceed min on every axis, got ") +
                                      "xyz"[k] + " from " + FormatNumber(min[k]) + " to " +
                                      FormatNumber(max[k]));
      }
    }
    const double rotate_z = f.Number("rotate_z", Closed(-360, 360), 0.0);
    const bool inward = f.Bool("inward", false);

    auto face_index = [](const std::string& label) {
      for (int i = 0; i < 6; ++i) {
        if (label == kBoxFaceLabels[i]) return i;
      }
      return -1;
    };
    bool omitted[6] = {false, false, false, false, false, false};
    if (f.Has("omit")) {
      for (const toml::node& element : f.Array("omit")) {
        const auto* s = element.as_string();
        const int i = s != nullptr ? face_index(s->get()) : -1;
        if (i < 0) {
          f.Fail(element,
                 "omit entries must be face names \"+x\", \"-x\", \"+y\", \"-y\", "
                 "\"+z\" or \"-z\", got " +
                     Describe(element));
        }
        if (omitted[i]) f.Fail(element, "face " + s->get() + " omitted twice");
        omitted[i] = true;
      }
    }
    std::optional<Rgb> face_colour[6];
    if (f.Has("faces")) {
      TomlFields faces(f.Table("faces"), path_, f.what() + " faces");
      faces.CheckKeys({"+x", "-x", "+y", "-y", "+z", "-z"});
      for (int i = 0; i < 6; ++i) {
        const toml::node* node = faces.table().get(kBoxFaceLabels[i]);
        if (node == nullptr) continue;
        if (omitted[i])
          faces.Fail(*node, std::string("face ") + kBoxFaceLabels[i] +
                                " is omitted and cannot have a material");
        face_colour[i] = node->is_string() ? LookUpMaterial(faces, *node)
                                           : ReadReflectance(faces, *node, kBoxFaceLabels[i]);
      }
    }
    std::optional<Rgb> box_colour;
    if (f.Has("material") || f.Has("reflectance")) box_colour = ReadColour(f);

    int kept = 0;
    for (int i = 0; i < 6; ++i) {
      if (omitted[i]) continue;
      ++kept;
      if (!face_colour[i] && !box_colour) {
        f.Fail(std::string("face ") + kBoxFaceLabels[i] +
               " has no material: give the box material or reflectance, or faces." +
               kBoxFaceLabels[i]);
      }
      Surface surface;
      surface.name = name + "/" + kBoxFaceLabels[i];
      surface.corners = BoxFace(min, max, rotate_z, inward, i);
      surface.reflectance = face_colour[i] ? *face_colour[i] : *box_colour;
      AddSurface(f, f.line(), std::move(surface), f.Required("max"));
    }
    if (kept == 0) f.Fail(f.Required("omit"), "every face is omitted");
  }

  void ReadMesh(const toml::table& table) {
    TomlFields f(table, path_, "mesh");
    f.NameFrom("file", "mesh");
    f.CheckKeys({"file", "translate", "scale", "rotate_z", "up", "material", "reflectance"});
    const std::string file = f.String("file");
    f.set_what("mesh " + Quoted(file));
    if (file.empty()) f.Fail(f.Required("file"), "file must not be empty");
    MeshPlacement placement;
    placement.translate = f.Vector("translate", Vec3{0, 0, 0});
    if (f.Has("scale")) {
      const toml::node& node = f.Required("scale");
      if (node.is_array()) {
        const auto& array = *node.as_array();
        if (array.size() != 3)
          f.Fail(node, "scale must be a number or [sx, sy, sz], got " + Describe(node));
        // Positive only: a mirror would turn every face's lit side inside out.
        for (size_t k = 0; k < 3; ++k)
          placement.scale[k] = f.ReadNumber(*array.get(k), "scale", Positive());
      } else {
        const double s = f.ReadNumber(node, "scale", Positive());
        placement.scale = Vec3{s, s, s};
      }
    }
    placement.rotate_z_deg = f.Number("rotate_z", Closed(-360, 360), 0.0);
    const std::string up = f.String("up", std::string("z"));
    if (up != "z" && up != "y")
      f.Fail(f.Required("up"), "up must be \"z\" or \"y\", got " + Describe(f.Required("up")));
    placement.y_up = up == "y";
    std::optional<Rgb> override_colour;
    if (f.Has("material") || f.Has("reflectance")) override_colour = ReadColour(f);

    const std::string obj_path = file.front() == '/' ? file : FolderOf(path_) + file;
    std::string obj_text, why;
    if (!ReadBoundedFile(obj_path, kMaxMeshFileBytes, &obj_text, &why)) {
      f.Fail(f.Required("file"), "cannot open OBJ file: " + why);
    }
    const ObjModel model = ParseObj(obj_text, obj_path, !override_colour.has_value());
    for (const ObjFace& face : model.faces) {
      Surface surface;
      surface.name = file + ":" + std::to_string(face.line);
      for (const Vec3& p : face.corners) surface.corners.push_back(placement.Apply(p));
      surface.reflectance = override_colour ? *override_colour : model.materials.at(face.material);
      const std::string problem = PolygonProblem(surface.corners);
      if (!problem.empty()) throw SceneError(obj_path, face.line, "face " + problem);
      surfaces_.emplace_back(f.line(), std::move(surface));  // LoadObj keeps only flat quads
    }
  }

  TomlFields root_;
  std::string path_;
  std::map<std::string, Rgb> materials_;
  std::map<std::string, int> object_lines_, luminaire_lines_, grid_lines_;
  std::vector<std::pair<int, Surface>> surfaces_;  // (line of the object, surface)
};

}  // namespace

Scene LoadScene(const std::string& toml_path) {
  std::string document, why;
  if (!ReadBoundedFile(toml_path, kMaxSceneFileBytes, &document, &why)) {
    throw SceneError(toml_path, 0, "cannot open scene file: " + why);
  }
  toml::table root;
  try {
    root = toml::parse(std::string_view(document), std::string_view(toml_path));
  } catch (const toml::parse_error& e) {
    throw SceneError(toml_path, static_cast<int>(e.source().begin.line),
                     "TOML syntax error: " + std::string(e.description()));
  }
  return SceneReader(root, toml_path).Read();
}

}  // namespace relight::baker
