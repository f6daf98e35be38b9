// Scenes built in code for the radiosity tests: quads, triangles, boxes.
#pragma once

#include <string>
#include <vector>

#include "relight/baker/scene.h"

namespace relight::baker::test_scenes {

inline Surface Quad(const char* name, Vec3 a, Vec3 b, Vec3 c, Vec3 d, Rgb rho = {0.5, 0.5, 0.5}) {
  Surface s;
  s.name = name;
  s.corners = {a, b, c, d};
  s.reflectance = rho;
  return s;
}

inline Surface Triangle(const char* name, Vec3 a, Vec3 b, Vec3 c, Rgb rho = {0.5, 0.5, 0.5}) {
  Surface s;
  s.name = name;
  s.corners = {a, b, c};
  s.reflectance = rho;
  return s;
}

// The six faces of an axis-aligned box, CCW seen from inside (lit side in).
inline std::vector<Surface> InwardBox(Vec3 lo, Vec3 hi, Rgb floor_rho, Rgb wall_rho, Rgb ceiling_rho) {
  const double x0 = lo[0], y0 = lo[1], z0 = lo[2], x1 = hi[0], y1 = hi[1], z1 = hi[2];
  return {
      Quad("floor", {x0, y0, z0}, {x1, y0, z0}, {x1, y1, z0}, {x0, y1, z0}, floor_rho),
      Quad("ceiling", {x0, y0, z1}, {x0, y1, z1}, {x1, y1, z1}, {x1, y0, z1}, ceiling_rho),
      Quad("wall -x", {x0, y0, z0}, {x0, y1, z0}, {x0, y1, z1}, {x0, y0, z1}, wall_rho),
      Quad("wall +x", {x1, y0, z0}, {x1, y0, z1}, {x1, y1, z1}, {x1, y1, z0}, wall_rho),
      Quad("wall -y", {x0, y0, z0}, {x0, y0, z1}, {x1, y0, z1}, {x1, y0, z0}, wall_rho),
      Quad("wall +y", {x0, y1, z0}, {x1, y1, z0}, {x1, y1, z1}, {x0, y1, z1}, wall_rho),
  };
}

// The six faces of an axis-aligned solid box, CCW seen from outside.
inline std::vector<Surface> OutwardBox(const std::string& name, Vec3 lo, Vec3 hi, Rgb rho) {
  const double x0 = lo[0], y0 = lo[1], z0 = lo[2], x1 = hi[0], y1 = hi[1], z1 = hi[2];
  std::vector<Surface> faces = {
      Quad("-z", {x0, y0, z0}, {x0, y1, z0}, {x1, y1, z0}, {x1, y0, z0}, rho),
      Quad("+z", {x0, y0, z1}, {x1, y0, z1}, {x1, y1, z1}, {x0, y1, z1}, rho),
      Quad("-x", {x0, y0, z0}, {x0, y0, z1}, {x0, y1, z1}, {x0, y1, z0}, rho),
      Quad("+x", {x1, y0, z0}, {x1, y1, z0}, {x1, y1, z1}, {x1, y0, z1}, rho),
      Quad("-y", {x0, y0, z0}, {x1, y0, z0}, {x1, y0, z1}, {x0, y0, z1}, rho),
      Quad("+y", {x0, y1, z0}, {x0, y1, z1}, {x1, y1, z1}, {x1, y1, z0}, rho),
  };
  for (Surface& f : faces) f.name = name + "/" + f.name;
  return faces;
}

// A closed unit box, uniform reflectance: the B = E / (1 - rho) test scene.
inline Scene ClosedBox(double patch_size_m, Rgb rho) {
  Scene s;
  s.name = "closed box";
  s.path = "closed_box.toml";
  s.patch_size_m = patch_size_m;
  s.surfaces = InwardBox({0, 0, 0}, {1, 1, 1}, rho, rho, rho);
  return s;
}

// A 5 x 4 work plane at 0.8 m over a 3 x 2.4 m area, facing up.
inline CalcGrid WorkplaneGrid() {
  CalcGrid g;
  g.name = "workplane";
  for (int i = 0; i < 5; ++i) {
    for (int j = 0; j < 4; ++j) {
      g.points.push_back({0.3 + 0.6 * i, 0.3 + 0.6 * j, 0.8});
      g.normals.push_back({0, 0, 1});
    }
  }
  return g;
}

}  // namespace relight::baker::test_scenes
