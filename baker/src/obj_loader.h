// Wavefront OBJ geometry and MTL diffuse colours for the scene loader.
//
// OBJ: v (x y z [w]), f with v, v/vt, v//vn, v/vt/vn corners (1-based,
// negative = relative to the end), usemtl, mtllib; vt and vn are counted so
// their indices can be checked but their values are not used: the winding
// (counter-clockwise seen from the lit side) gives the normal. Other
// statements (o, g, s, l, p, ...) are ignored. Triangles stay triangles,
// quads stay quads when planar and convex (else two triangles), larger
// polygons become a triangle fan.
// MTL: newmtl and Kd (RGB reflectance in [0, 1)); other statements ignored.
// Errors throw SceneError naming the .obj or .mtl file and line.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "relight/baker/scene.h"

namespace relight::baker {

struct ObjFace {
  std::vector<Vec3> corners;  // 3 or 4, in the file's units and frame
  std::string material;       // usemtl in effect, "" if none (or materials not read)
  int line = 0;               // of the f statement
};

struct ObjModel {
  std::vector<ObjFace> faces;
  std::map<std::string, Rgb> materials;  // from every mtllib, by name
};

// Reads `path` (a regular file of at most kMaxMeshFileBytes, bounded_read.h);
// mtllib paths resolve against its folder. With read_materials false,
// mtllib and usemtl are skipped (the scene gives the material).
ObjModel LoadObj(const std::string& path, bool read_materials);
// The same for a file's text already read; `path` names it in errors and
// places its mtllib files.
ObjModel ParseObj(const std::string& text, const std::string& path, bool read_materials);

}  // namespace relight::baker
