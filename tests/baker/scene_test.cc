// Scene input: the two fixtures load as described, every class of bad input
// is a SceneError naming file:line and what was expected, OBJ/MTL details,
// Lid::Evaluate against closed forms, and the pan/tilt convention.
#include "relight/baker/scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

#include "relight/baker/photometry.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 Sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double Length(const Vec3& a) { return std::sqrt(Dot(a, a)); }
Vec3 Normalised(const Vec3& a) {
  const double l = Length(a);
  return {a[0] / l, a[1] / l, a[2] / l};
}

// Area-weighted normal (twice the area long), independent of the loader's own code.
Vec3 AreaNormal(const Surface& s) {
  Vec3 n{0, 0, 0};
  for (size_t i = 1; i + 1 < s.corners.size(); ++i) {
    const Vec3 c = Cross(Sub(s.corners[i], s.corners[0]), Sub(s.corners[i + 1], s.corners[0]));
    for (int k = 0; k < 3; ++k) n[k] += c[k];
  }
  return n;
}
double Area(const Surface& s) { return 0.5 * Length(AreaNormal(s)); }
Vec3 Centroid(const Surface& s) {
  Vec3 c{0, 0, 0};
  for (const Vec3& p : s.corners) {
    for (int k = 0; k < 3; ++k) c[k] += p[k] / static_cast<double>(s.corners.size());
  }
  return c;
}
// Patches if every surface were cut into patch_size squares (what the brief budgets).
double EstimatedPatches(const Scene& scene) {
  double area = 0;
  for (const Surface& s : scene.surfaces) area += Area(s);
  return area / (scene.patch_size_m * scene.patch_size_m);
}
const Surface* FindSurface(const Scene& scene, const std::string& name) {
  for (const Surface& s : scene.surfaces) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

std::string FixturePath(const std::string& name) {
  return std::string(RELIGHT_SOURCE_DIR) + "/fixtures/" + name;
}

// A fresh folder per test for scene, OBJ and MTL text.
class SceneFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = ::testing::TempDir() + "relight_scene_XXXXXX";
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
  }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }

  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = dir_ + "/" + name;
    std::ofstream(path) << text;
    return path;
  }

  // A valid scene header; the tests append the object under test.
  static std::string Header() {
    return "[scene]\n"                // 1
           "name = \"t\"\n"           // 2
           "[camera]\n"               // 3
           "position = [0, -3, 1]\n"  // 4
           "target = [0, 0, 1]\n"     // 5
           "fov = 50\n"               // 6
           "[[material]]\n"           // 7
           "name = \"grey\"\n"        // 8
           "reflectance = 0.5\n";     // 9
  }
  static constexpr int kHeaderLines = 9;
  static std::string Floor() {
    return "[[quad]]\n"
           "name = \"floor\"\n"
           "corners = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]\n"
           "material = \"grey\"\n";
  }

  // Loads `text` and expects a SceneError at file:line whose message holds every piece.
  void ExpectError(const std::string& text, int line, std::initializer_list<std::string> pieces,
                   const std::string& file_name = "scene.toml") {
    const std::string path = Write("scene.toml", text);
    ExpectErrorAt(path, dir_ + "/" + file_name, line, pieces);
  }
  static void ExpectErrorAt(const std::string& scene_path, const std::string& error_file, int line,
                            std::initializer_list<std::string> pieces) {
    try {
      LoadScene(scene_path);
      ADD_FAILURE() << "no SceneError for " << scene_path;
    } catch (const SceneError& e) {
      const std::string message = e.what();
      EXPECT_EQ(e.file(), error_file) << message;
      EXPECT_EQ(e.line(), line) << message;
      const std::string where = line > 0 ? error_file + ":" + std::to_string(line) : error_file;
      EXPECT_EQ(message.rfind(where + ": ", 0), 0u) << message;
      for (const std::string& piece : pieces) {
        EXPECT_NE(message.find(piece), std::string::npos)
            << "'" << piece << "' not in: " << message;
      }
    }
  }

  std::string dir_;
};

// --- fixtures -------------------------------------------------------------

TEST(Fixtures, CornellBoxLoadsWithPublishedGeometry) {
  const Scene scene = LoadScene(FixturePath("cornell_box.toml"));
  EXPECT_EQ(scene.name, "cornell_box");
  EXPECT_DOUBLE_EQ(scene.patch_size_m, 0.04);
  ASSERT_EQ(scene.surfaces.size(), 15u);  // 5 walls + 2 blocks x 5 faces
  EXPECT_LT(EstimatedPatches(scene), 1500.0);

  // Walls face into the box; block faces face away from their block.
  const Vec3 box_centre{0.278, -0.2796, 0.2744};
  for (const Surface& s : scene.surfaces) {
    const Vec3 n = AreaNormal(s);
    const bool block = s.name.find("_block_") != std::string::npos;
    if (!block) {
      EXPECT_GT(Dot(n, Sub(box_centre, Centroid(s))), 0.0) << s.name;
      continue;
    }
    const std::string prefix = s.name.substr(0, s.name.find("_block_") + 7);
    Vec3 block_centre{0, 0, 0};
    int faces = 0;
    for (const Surface& t : scene.surfaces) {
      if (t.name.rfind(prefix, 0) != 0) continue;
      const Vec3 c = Centroid(t);
      for (int k = 0; k < 3; ++k) block_centre[k] += c[k];
      ++faces;
    }
    for (int k = 0; k < 3; ++k) block_centre[k] /= faces;
    EXPECT_GT(Dot(n, Sub(Centroid(s), block_centre)), 0.0) << s.name;
  }
  // The floor: 552.8 x 559.2 mm at the front edge; the ceiling 548.8 mm up.
  const Surface* floor = FindSurface(scene, "floor");
  ASSERT_NE(floor, nullptr);
  EXPECT_NEAR(Normalised(AreaNormal(*floor))[2], 1.0, 1e-12);
  EXPECT_NEAR(floor->corners[0][0], 0.5528, 1e-12);
  EXPECT_NEAR(floor->corners[2][1], -0.5592, 1e-12);
  EXPECT_NEAR(FindSurface(scene, "ceiling")->corners[0][2], 0.5488, 1e-12);
  EXPECT_EQ(FindSurface(scene, "left_wall")->reflectance, (Rgb{0.63, 0.065, 0.05}));
  // Warped by 0.8 mm in the published data: projected onto its mean plane.
  const Surface* left = FindSurface(scene, "left_wall");
  const Vec3 left_n = Normalised(AreaNormal(*left));
  for (const Vec3& p : left->corners) {
    EXPECT_NEAR(Dot(Sub(p, left->corners[0]), left_n), 0.0, 1e-15);
  }
  EXPECT_NEAR(left->corners[0][0], 0.5528, 0.001);
  EXPECT_EQ(FindSurface(scene, "right_wall")->reflectance, (Rgb{0.14, 0.45, 0.091}));
  EXPECT_EQ(FindSurface(scene, "tall_block_top")->reflectance, (Rgb{0.73, 0.73, 0.73}));
  EXPECT_NEAR(FindSurface(scene, "tall_block_top")->corners[0][2], 0.33, 1e-12);

  // Camera at the published viewpoint; fov = 2 atan(12.5 / 35).
  EXPECT_NEAR(scene.camera.position[1], 0.8, 1e-12);
  EXPECT_NEAR(scene.camera.fov_y_deg, 2 * std::atan(12.5 / 35) * 180 / kPi, 0.01);

  ASSERT_EQ(scene.luminaires.size(), 1u);
  const Luminaire& spot = scene.luminaires[0];
  EXPECT_EQ(spot.name, "spot");
  EXPECT_EQ(spot.mounting, MountingKind::kHanging);
  EXPECT_EQ(spot.sh_degree, 8);
  EXPECT_EQ(spot.lid.kind, LidKind::kCosPower);
  EXPECT_EQ(spot.lid.exponent, 10.0);
  EXPECT_EQ(spot.lid.spread_deg, 90.0);
  const Vec3 axis = BeamAxis(spot.mounting, spot.pan_deg, spot.tilt_deg);
  EXPECT_NEAR(axis[2], -1.0, 1e-12);
  EXPECT_NEAR(0.5488 - spot.position[2], 0.01, 1e-9);
  // Direct illuminance on the floor straight below: I(0) / d^2.
  const double floor_lux = spot.lid.Evaluate(0) / (spot.position[2] * spot.position[2]);
  EXPECT_GE(floor_lux, 30.0);
  EXPECT_LE(floor_lux, 100.0);

  ASSERT_EQ(scene.grids.size(), 1u);
  const CalcGrid& grid = scene.grids[0];
  EXPECT_EQ(grid.name, "floor");
  EXPECT_EQ(grid.columns, 10);
  EXPECT_EQ(grid.rows, 10);
  ASSERT_EQ(grid.points.size(), 100u);
  for (size_t i = 0; i < grid.points.size(); ++i) {
    EXPECT_NEAR(grid.normals[i][2], 1.0, 1e-15);
    EXPECT_NEAR(grid.points[i][2], 0.001, 1e-12);
    EXPECT_GT(grid.points[i][0], 0.0);
    EXPECT_LT(grid.points[i][0], 0.5496);
    EXPECT_LT(grid.points[i][1], 0.0);
    EXPECT_GT(grid.points[i][1], -0.5592);
  }
}

TEST(Fixtures, LivingRoomLoads) {
  const Scene scene = LoadScene(FixturePath("living_room.toml"));
  EXPECT_EQ(scene.name, "living_room");
  // room 6, seat 3, back 5, arms 2 x 5, rug 1, table 5, shelf 4,
  // side table 8 sides + octagonal top as a 6-triangle fan.
  EXPECT_EQ(scene.surfaces.size(), 48u);
  const double patches = EstimatedPatches(scene);
  EXPECT_GE(patches, 2000.0);
  EXPECT_LE(patches, 3000.0);

  const Surface* floor = FindSurface(scene, "room/-z");
  const Surface* ceiling = FindSurface(scene, "room/+z");
  ASSERT_NE(floor, nullptr);
  ASSERT_NE(ceiling, nullptr);
  EXPECT_NEAR(Normalised(AreaNormal(*floor))[2], 1.0, 1e-12);  // inward: floor faces up
  EXPECT_NEAR(Normalised(AreaNormal(*ceiling))[2], -1.0, 1e-12);
  EXPECT_NEAR(Area(*floor), 27.0, 1e-9);
  EXPECT_EQ(floor->reflectance, (Rgb{0.35, 0.25, 0.15}));
  EXPECT_EQ(ceiling->reflectance, (Rgb{0.8, 0.8, 0.8}));
  EXPECT_EQ(FindSurface(scene, "room/+x")->reflectance, (Rgb{0.7, 0.68, 0.62}));
  EXPECT_EQ(FindSurface(scene, "sofa_seat/-x"), nullptr);  // omitted

  int obj_faces = 0, marble = 0;
  for (const Surface& s : scene.surfaces) {
    if (s.name.rfind("living_room/side_table.obj:", 0) != 0) continue;
    ++obj_faces;
    const Vec3 n = Normalised(AreaNormal(s));
    if (s.reflectance == Rgb{0.75, 0.74, 0.72}) {
      ++marble;
      EXPECT_NEAR(n[2], 1.0, 1e-9);
      EXPECT_NEAR(s.corners[0][2], 0.55, 1e-12);
    } else {
      EXPECT_EQ(s.reflectance, (Rgb{0.30, 0.20, 0.12}));
      EXPECT_NEAR(n[2], 0.0, 1e-9);
      // Placed around (4.8, 4.1): the side faces look away from that axis.
      const Vec3 c = Centroid(s);
      EXPECT_GT(n[0] * (c[0] - 4.8) + n[1] * (c[1] - 4.1), 0.0) << s.name;
    }
  }
  EXPECT_EQ(obj_faces, 14);
  EXPECT_EQ(marble, 6);

  ASSERT_EQ(scene.luminaires.size(), 3u);
  EXPECT_EQ(scene.luminaires[0].name, "ceiling_wide");
  EXPECT_EQ(scene.luminaires[0].sh_degree, 5);
  EXPECT_EQ(scene.luminaires[1].name, "ceiling_spot");
  EXPECT_EQ(scene.luminaires[1].sh_degree, 8);
  EXPECT_EQ(scene.luminaires[2].name, "corner_uplight");
  EXPECT_EQ(scene.luminaires[2].mounting, MountingKind::kStanding);
  EXPECT_EQ(scene.luminaires[2].lid.kind, LidKind::kTable);
  EXPECT_EQ(scene.luminaires[2].sh_degree, 5);
  // aim_at became pan/tilt whose beam axis points at the table.
  const Luminaire& spot = scene.luminaires[1];
  const Vec3 axis = BeamAxis(spot.mounting, spot.pan_deg, spot.tilt_deg);
  const Vec3 to_table = Normalised(Sub(Vec3{3.0, 2.45, 0.4}, spot.position));
  EXPECT_NEAR(Dot(axis, to_table), 1.0, 1e-12);
  const Luminaire& up = scene.luminaires[2];
  EXPECT_GT(BeamAxis(up.mounting, up.pan_deg, up.tilt_deg)[2], 0.5);  // aimed up

  // Unoccluded direct illuminance on the floor grid from all three: a few
  // hundred lux on average (E = I(gamma) cos(theta) / d^2).
  ASSERT_EQ(scene.grids.size(), 1u);
  const CalcGrid& grid = scene.grids[0];
  ASSERT_EQ(grid.points.size(), 108u);
  double sum_lux = 0;
  for (size_t i = 0; i < grid.points.size(); ++i) {
    for (const Luminaire& l : scene.luminaires) {
      const Vec3 d = Sub(l.position, grid.points[i]);
      const double r = Length(d);
      const double cos_receiver = Dot(d, grid.normals[i]) / r;
      if (cos_receiver <= 0) continue;
      const Vec3 beam = BeamAxis(l.mounting, l.pan_deg, l.tilt_deg);
      const double gamma = std::acos(std::clamp(-Dot(d, beam) / r, -1.0, 1.0)) * 180 / kPi;
      sum_lux += l.lid.Evaluate(gamma) * cos_receiver / (r * r);
    }
  }
  const double mean_lux = sum_lux / static_cast<double>(grid.points.size());
  EXPECT_GE(mean_lux, 100.0);
  EXPECT_LE(mean_lux, 500.0);
}

TEST_F(SceneFiles, DocumentedExampleLoads) {
  std::ifstream doc(std::string(RELIGHT_SOURCE_DIR) + "/docs/scene-format.md");
  ASSERT_TRUE(doc);
  std::string line, example;
  bool inside = false;
  while (std::getline(doc, line)) {
    if (line == "```toml") {
      inside = true;
    } else if (inside && line == "```") {
      break;
    } else if (inside) {
      example += line + "\n";
    }
  }
  ASSERT_FALSE(example.empty());
  const Scene scene = LoadScene(Write("example.toml", example));
  EXPECT_EQ(scene.surfaces.size(), 6u);
  ASSERT_EQ(scene.luminaires.size(), 1u);
  ASSERT_EQ(scene.grids.size(), 1u);
  EXPECT_EQ(scene.grids[0].points.size(), 48u);
}

// --- scene contents --------------------------------------------------------

TEST_F(SceneFiles, BoxFacesRotateOmitAndOverride) {
  const std::string path =
      Write("scene.toml", Header() +
                              "[[material]]\nname = \"red\"\nreflectance = [0.6, 0.1, 0.1]\n"
                              "[[box]]\nname = \"b\"\nmin = [0, 0, 0]\nmax = [2, 1, 1]\n"
                              "rotate_z = 90\nomit = [\"-z\"]\nmaterial = \"grey\"\n"
                              "faces = { \"+x\" = \"red\", \"+y\" = [0.1, 0.2, 0.3] }\n"
                              "[[box]]\nname = \"room\"\nmin = [-5, -5, 0]\nmax = [5, 5, 3]\n"
                              "inward = true\nreflectance = 0.4\n");
  const Scene scene = LoadScene(path);
  ASSERT_EQ(scene.surfaces.size(), 11u);
  const Vec3 centre{1, 0.5, 0.5};
  for (const Surface& s : scene.surfaces) {
    const Vec3 n = Normalised(AreaNormal(s));
    if (s.name.rfind("b/", 0) == 0) {
      EXPECT_GT(Dot(n, Sub(Centroid(s), centre)), 0.0) << s.name;  // outward
    } else {
      EXPECT_LT(Dot(n, Sub(Centroid(s), Vec3{0, 0, 1.5})), 0.0) << s.name;  // inward
      EXPECT_EQ(s.reflectance, (Rgb{0.4, 0.4, 0.4}));
    }
  }
  // Turned 90 degrees about (1, 0.5): the +x face now faces +y, 1 m from the centre axis.
  const Surface* px = FindSurface(scene, "b/+x");
  ASSERT_NE(px, nullptr);
  EXPECT_EQ(px->reflectance, (Rgb{0.6, 0.1, 0.1}));
  const Vec3 n = Normalised(AreaNormal(*px));
  EXPECT_NEAR(n[1], 1.0, 1e-12);
  EXPECT_NEAR(Centroid(*px)[1], 1.5, 1e-12);
  EXPECT_NEAR(Area(*px), 1.0, 1e-12);
  EXPECT_EQ(FindSurface(scene, "b/+y")->reflectance, (Rgb{0.1, 0.2, 0.3}));
  EXPECT_EQ(FindSurface(scene, "b/-x")->reflectance, (Rgb{0.5, 0.5, 0.5}));
  EXPECT_EQ(FindSurface(scene, "b/-z"), nullptr);
}

TEST_F(SceneFiles, SlightlyWarpedQuadIsProjectedOntoItsMeanPlane) {
  // Corner 3 is 2 mm off: 0.1% of the 1.41 m diagonal, inside the 0.5% tolerance.
  const std::vector<Vec3> given{{0, 0, 0}, {0, 0, 1}, {0.002, 1, 1}, {0, 1, 0}};
  const std::string path =
      Write("scene.toml", Header() + Floor() +
                              "[[quad]]\nname = \"wall\"\nmaterial = \"grey\"\n"
                              "corners = [[0, 0, 0], [0, 0, 1], [0.002, 1, 1], [0, 1, 0]]\n");
  const Scene scene = LoadScene(path);
  ASSERT_EQ(scene.surfaces.size(), 2u);
  const Surface& wall = scene.surfaces[1];
  ASSERT_EQ(wall.corners.size(), 4u);
  const Vec3 n = Normalised(AreaNormal(wall));
  EXPECT_LT(n[0], -0.99);  // winding kept: faces -x
  // Exactly planar now: every corner on the plane through corner 0.
  for (const Vec3& p : wall.corners) EXPECT_NEAR(Dot(Sub(p, wall.corners[0]), n), 0.0, 1e-15);
  // Each corner moved along the normal by at most the warp (2 mm), by a
  // quarter of it in the symmetric case: 0.5 mm.
  for (size_t i = 0; i < 4; ++i) {
    const Vec3 moved = Sub(wall.corners[i], given[i]);
    EXPECT_NEAR(Length(moved), 0.0005, 1e-6) << i;
    EXPECT_NEAR(std::fabs(Dot(Normalised(moved), n)), 1.0, 1e-9) << i;
  }
}

TEST_F(SceneFiles, RectangleGridPointsAreCellCentres) {
  const std::string path =
      Write("scene.toml", Header() + Floor() +
                              "[[grid]]\nname = \"wall\"\norigin = [0, 0, 0]\nu = [2, 0, 0]\n"
                              "v = [0, 0, 1]\ncolumns = 4\nrows = 2\n"
                              "[[grid]]\nname = \"list\"\npoints = [[1, 2, 3], [4, 5, 6]]\n"
                              "normal = [0, 0, 2]\n");
  const Scene scene = LoadScene(path);
  ASSERT_EQ(scene.grids.size(), 2u);
  const CalcGrid& wall = scene.grids[0];
  ASSERT_EQ(wall.points.size(), 8u);
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 4; ++c) {
      const Vec3& p = wall.points[static_cast<size_t>(r * 4 + c)];
      EXPECT_NEAR(p[0], (c + 0.5) * 0.5, 1e-12);
      EXPECT_NEAR(p[2], (r + 0.5) * 0.5, 1e-12);
    }
  }
  // normal = u x v normalised: (1,0,0) x (0,0,1) = (0,-1,0).
  EXPECT_NEAR(wall.normals[0][1], -1.0, 1e-12);
  const CalcGrid& list = scene.grids[1];
  EXPECT_EQ(list.columns, 0);
  EXPECT_EQ(list.rows, 0);
  ASSERT_EQ(list.points.size(), 2u);
  EXPECT_EQ(list.points[1], (Vec3{4, 5, 6}));
  EXPECT_EQ(list.normals[1], (Vec3{0, 0, 1}));
}

TEST_F(SceneFiles, ObjCornerFormatsPolygonsAndPlacement) {
  Write("m.mtl", "newmtl a\nKd 0.1 0.2 0.3\nmap_Kd tex.png\nnewmtl b\nKd 0.4\n");
  // A pentagon (fan of 3), a non-planar quad (two triangles), a planar quad
  // with v/vt/vn and negative indices, a triangle with v/vt.
  Write("m.obj",
        "mtllib m.mtl\n"                                          // 1
        "v 0 0 0\nv 1 0 0\nv 1.5 1 0\nv 0.5 1.5 0\nv -0.5 1 0\n"  // 2-6
        "vt 0 0\nvn 0 0 1\n"                                      // 7-8
        "usemtl a\n"                                              // 9
        "f 1 2 3 4 5\n"                                           // 10
        "v 0 0 1\nv 1 0 1\nv 1 1 1.5\nv 0 1 1\n"                  // 11-14
        "usemtl b\n"                                              // 15
        "f 6 7 8 9\n"                                             // 16
        "v 0 0 2\nv 1 0 2\nv 1 1 2\nv 0 1 2\n"                    // 17-20
        "f -4/1/1 -3/1/1 -2/-1/-1 -1/1/1\n"                       // 21
        "g part\ns 1\nf 1/1 2/1 4/1\n");                          // 22-24
  const std::string path =
      Write("scene.toml", Header() +
                              "[[mesh]]\nfile = \"m.obj\"\nup = \"y\"\nscale = 2\nrotate_z = 90\n"
                              "translate = [10, 0, 0]\n");
  const Scene scene = LoadScene(path);
  ASSERT_EQ(scene.surfaces.size(), 3u + 2u + 1u + 1u);
  EXPECT_EQ(scene.surfaces[0].name, "m.obj:10");
  EXPECT_EQ(scene.surfaces[3].name, "m.obj:16");
  EXPECT_EQ(scene.surfaces[5].name, "m.obj:21");
  EXPECT_EQ(scene.surfaces[6].name, "m.obj:24");
  EXPECT_EQ(scene.surfaces[0].reflectance, (Rgb{0.1, 0.2, 0.3}));
  EXPECT_EQ(scene.surfaces[3].reflectance, (Rgb{0.4, 0.4, 0.4}));
  ASSERT_EQ(scene.surfaces[5].corners.size(), 4u);
  double pentagon_area = 0;
  for (int i = 0; i < 3; ++i) pentagon_area += Area(scene.surfaces[static_cast<size_t>(i)]);
  // Shoelace area of the pentagon, times scale^2.
  EXPECT_NEAR(pentagon_area, 4.0 * 2.0, 1e-12);
  // (x, y, z) -> y-up (x, -z, y) -> x2 -> turned 90 deg: (2z, 2x, 2y) -> + (10, 0, 0).
  // OBJ vertex 2 = (1, 0, 0) lands at (10, 2, 0).
  const Vec3 v2 = scene.surfaces[0].corners[1];
  EXPECT_NEAR(v2[0], 10.0, 1e-12);
  EXPECT_NEAR(v2[1], 2.0, 1e-12);
  EXPECT_NEAR(v2[2], 0.0, 1e-12);
  // The pentagon faced +z in the file; y-up turns that to -y, the turn to +x.
  EXPECT_NEAR(Normalised(AreaNormal(scene.surfaces[0]))[0], 1.0, 1e-12);
}

TEST_F(SceneFiles, MeshMaterialOverridesMtl) {
  Write("m.obj", "mtllib missing.mtl\nusemtl x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string path =
      Write("scene.toml", Header() + "[[mesh]]\nfile = \"m.obj\"\nmaterial = \"grey\"\n");
  const Scene scene = LoadScene(path);
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_EQ(scene.surfaces[0].reflectance, (Rgb{0.5, 0.5, 0.5}));
}

TEST_F(SceneFiles, LuminaireDefaultsAndTableLid) {
  const std::string path =
      Write("scene.toml",
            Header() + Floor() +
                "[[luminaire]]\nname = \"a-1_B\"\nposition = [0, 0, 2]\nmounting = \"standing\"\n"
                "pan = 30\ntilt = 20\nsigma = false\n"
                "[luminaire.lid]\ntype = \"table\"\ngamma = [0, 10, 90.5]\ncandela = [5, 7, 0]\n");
  const Scene scene = LoadScene(path);
  ASSERT_EQ(scene.luminaires.size(), 1u);
  const Luminaire& l = scene.luminaires[0];
  EXPECT_EQ(l.name, "a-1_B");
  EXPECT_EQ(l.line, kHeaderLines + 5);
  EXPECT_EQ(l.pan_deg, 30.0);
  EXPECT_EQ(l.tilt_deg, 20.0);
  EXPECT_EQ(l.dimmer, 1.0);
  EXPECT_EQ(l.colour, (Rgb{1, 1, 1}));
  EXPECT_EQ(l.sh_degree, 8);
  ASSERT_TRUE(l.use_sigma.has_value());
  EXPECT_FALSE(*l.use_sigma);
  EXPECT_EQ(l.lid.gamma_deg, (std::vector<double>{0, 10, 90.5}));
  EXPECT_EQ(l.lid.candela, (std::vector<double>{5, 7, 0}));
  EXPECT_EQ(l.lid.peak_cd, 7.0);
  EXPECT_EQ(scene.patch_size_m, 0.25);
  EXPECT_EQ(scene.white_cd_m2, 0.0);
}

// --- errors: file:line and what was expected -------------------------------

TEST_F(SceneFiles, MissingSceneFile) {
  ExpectErrorAt(dir_ + "/nope.toml", dir_ + "/nope.toml", 0, {"cannot open scene file"});
}

TEST_F(SceneFiles, BadTomlSyntax) {
  ExpectError(Header() + "[[quad]]\nname = \"floor\ncorners = []\n", kHeaderLines + 2,
              {"TOML syntax error"});
}

TEST_F(SceneFiles, MissingKey) {
  ExpectError(Header() + "\n[[quad]]\nname = \"floor\"\nmaterial = \"grey\"\n", kHeaderLines + 2,
              {"quad 'floor'", "missing key 'corners'"});
  ExpectError("[camera]\nposition = [0, 0, 0]\ntarget = [1, 0, 0]\nfov = 40\n" + Floor(), 0,
              {"missing table [scene]"});
}

TEST_F(SceneFiles, WrongType) {
  ExpectError(Header() + Floor() +
                  "[[luminaire]]\nname = \"spot1\"\nposition = [0, 0, 2]\nmounting = \"hanging\"\n"
                  "sh_degree = \"eight\"\nlid = { type = \"isotropic\", peak_cd = 100 }\n",
              kHeaderLines + 4 + 5,
              {"luminaire 'spot1'", "sh_degree must be an integer 0..22, got \"eight\""});
  ExpectError(Header() +
                  "[[quad]]\nname = \"q\"\ncorners = [[0, 0, 0], [1, 0, 0], [1, 1, 0], \"x\"]\n"
                  "material = \"grey\"\n",
              kHeaderLines + 3,
              {"quad 'q'", "corner 4 must be an array of 3 numbers", "got \"x\""});
  ExpectError(Header() + "[quad]\nname = \"q\"\n", kHeaderLines + 1, {"must be written [[quad]]"});
}

TEST_F(SceneFiles, ShDegreeOutOfRangeNamesLineAndRange) {
  ExpectError(Header() + Floor() +
                  "[[luminaire]]\nname = \"spot1\"\nposition = [0, 0, 2]\nmounting = \"hanging\"\n"
                  "sh_degree = 23\nlid = { type = \"isotropic\", peak_cd = 100 }\n",
              kHeaderLines + 4 + 5,
              {"luminaire 'spot1': sh_degree must be an integer 0..22, got 23"});
}

TEST_F(SceneFiles, UnknownKey) {
  ExpectError(Header() + "[[material]]\nname = \"m\"\nreflectence = 0.3\n", kHeaderLines + 3,
              {"material 'm'", "unknown key 'reflectence'", "did you mean 'reflectance'"});
  ExpectError(Header() + Floor() + "[[lumiaire]]\nname = \"x\"\n", kHeaderLines + 4 + 1,
              {"unknown key 'lumiaire'", "did you mean 'luminaire'"});
  ExpectError(Header() + Floor() +
                  "[[luminaire]]\nname = \"s\"\nposition = [0, 0, 2]\nmounting = \"hanging\"\n"
                  "lid = { type = \"cos\", exponent = 2, spread = 60, peak = 100 }\n",
              kHeaderLines + 4 + 5,
              {"luminaire 's' lid", "unknown key 'peak'", "did you mean 'peak_cd'"});
}

TEST_F(SceneFiles, ReflectanceOutOfRange) {
  ExpectError(Header() + "[[material]]\nname = \"white\"\nreflectance = [0.7, 1.0, 0.7]\n",
              kHeaderLines + 3,
              {"material 'white'", "reflectance must be a number in [0, 1), got 1.0"});
  ExpectError(Header() +
                  "[[quad]]\nname = \"q\"\ncorners = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]\n"
                  "reflectance = -0.1\n",
              kHeaderLines + 4, {"quad 'q'", "reflectance must be a number in [0, 1), got -0.1"});
}

TEST_F(SceneFiles, UnknownMaterial) {
  ExpectError(Header() +
                  "[[quad]]\nname = \"q\"\ncorners = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]\n"
                  "material = \"gray\"\n",
              kHeaderLines + 4, {"unknown material 'gray'", "defined: grey"});
}

TEST_F(SceneFiles, BadPolygons) {
  // 10 cm out of plane on a 1 m quad: far beyond 0.5% of the 1.41 m diagonal.
  ExpectError(Header() +
                  "[[quad]]\nname = \"warped\"\n"
                  "corners = [[0, 0, 0], [1, 0, 0], [1, 1, 0.1], [0, 1, 0]]\nmaterial = \"grey\"\n",
              kHeaderLines + 3, {"quad 'warped'", "not planar", "tolerance"});
  ExpectError(
      Header() +
          "[[quad]]\nname = \"dart\"\n"
          "corners = [[0, 0, 0], [1, 0, 0], [0.3, 0.3, 0], [0, 1, 0]]\nmaterial = \"grey\"\n",
      kHeaderLines + 3, {"quad 'dart'", "not strictly convex at corner 3"});
  ExpectError(Header() +
                  "[[triangle]]\nname = \"line\"\n"
                  "corners = [[0, 0, 0], [1, 0, 0], [2, 0, 0]]\nmaterial = \"grey\"\n",
              kHeaderLines + 3, {"triangle 'line'", "degenerate"});
  ExpectError(Header() +
                  "[[triangle]]\nname = \"t\"\n"
                  "corners = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]\nmaterial = \"grey\"\n",
              kHeaderLines + 3, {"corners must be 3 points"});
  ExpectError(
      Header() +
          "[[box]]\nname = \"flat\"\nmin = [0, 0, 0]\nmax = [1, 1, 0]\nmaterial = \"grey\"\n",
      kHeaderLines + 4, {"box 'flat'", "max must exceed min on every axis, got z from 0 to 0"});
}

TEST_F(SceneFiles, BadLidTable) {
  const std::string lum =
      "[[luminaire]]\nname = \"u\"\nposition = [0, 0, 1]\nmounting = \"standing\"\n";
  const int lid_line = kHeaderLines + 4 + 5;
  ExpectError(
      Header() + Floor() + lum + "lid = { type = \"table\", gamma = [5, 10], candela = [1, 1] }\n",
      lid_line, {"luminaire 'u' lid", "gamma must start at 0, got 5"});
  ExpectError(Header() + Floor() + lum +
                  "lid = { type = \"table\", gamma = [0, 20, 10], candela = [1, 1, 1] }\n",
              lid_line, {"gamma must be strictly increasing, got 10 after 20"});
  ExpectError(
      Header() + Floor() + lum + "lid = { type = \"table\", gamma = [0, 190], candela = [1, 1] }\n",
      lid_line, {"gamma must be a number in [0, 180], got 190"});
  ExpectError(
      Header() + Floor() + lum + "lid = { type = \"table\", gamma = [0, 90], candela = [1, -2] }\n",
      lid_line, {"candela must be a number >= 0, got -2"});
  ExpectError(
      Header() + Floor() + lum + "lid = { type = \"table\", gamma = [0, 90], candela = [1] }\n",
      lid_line, {"candela must have one value per gamma angle (2)"});
  ExpectError(Header() + Floor() + lum +
                  "lid = { type = \"cos\", exponent = 2, spread = 0, peak_cd = 9 }\n",
              lid_line, {"spread must be a number in (0, 180], got 0"});
  ExpectError(Header() + Floor() + lum + "lid = { type = \"isotropic\", peak_cd = 0 }\n", lid_line,
              {"peak_cd must be a number > 0, got 0"});
  ExpectError(Header() + Floor() + lum + "lid = { type = \"ies\" }\n", lid_line,
              {"type must be \"isotropic\", \"cos\", \"table\", \"beam\" or \"file\", got \"ies\""});
}

// A zoom optic's beam model (docs/scene-format.md, lid type "beam").
TEST_F(SceneFiles, BeamLidParsesWithItsDefaults) {
  const std::string lum =
      "[[luminaire]]\nname = \"z\"\nposition = [0, 0, 2]\nmounting = \"hanging\"\n";
  const Scene scene = LoadScene(Write(
      "scene.toml", Header() + Floor() + lum +
                        "lid = { type = \"beam\", beam_angle = 20, lumens = 1000, zoom = [8, 40] }\n" +
                        lum.substr(0, lum.find("name")) + "name = \"p\"\nposition = [1, 0, 2]\n" +
                        "mounting = \"hanging\"\nsh_degree = 5\n" +
                        "lid = { type = \"beam\", beam_angle = 30, field_angle = 45, peak_cd = 500 }\n"));
  const Lid& zoom = scene.luminaires[0].lid;
  EXPECT_EQ(zoom.kind, LidKind::kBeam);
  EXPECT_TRUE(zoom.zooms());
  EXPECT_FALSE(scene.luminaires[0].sh_degree_given);
  EXPECT_DOUBLE_EQ(zoom.zoom_min_deg, 8);
  EXPECT_DOUBLE_EQ(zoom.zoom_max_deg, 40);
  EXPECT_DOUBLE_EQ(zoom.beam_exponent, 2.0);  // no field angle: a Gaussian
  EXPECT_NEAR(zoom.Evaluate(10) / zoom.peak_cd, 0.5, 1e-12);  // half peak at half the beam angle
  const Lid& fixed = scene.luminaires[1].lid;
  EXPECT_FALSE(fixed.zooms());
  EXPECT_TRUE(scene.luminaires[1].sh_degree_given);
  EXPECT_DOUBLE_EQ(fixed.peak_cd, 500);
  EXPECT_NEAR(fixed.Evaluate(15) / 500, 0.5, 1e-12);
  EXPECT_NEAR(fixed.Evaluate(22.5) / 500, 0.1, 1e-12);  // a tenth at half the field angle
}

TEST_F(SceneFiles, BadBeamLid) {
  const std::string lum =
      "[[luminaire]]\nname = \"u\"\nposition = [0, 0, 1]\nmounting = \"standing\"\n";
  const int lid_line = kHeaderLines + 4 + 5;
  const auto beam = [&](const std::string& keys) {
    return Header() + Floor() + lum + "lid = { type = \"beam\", " + keys + " }\n";
  };
  ExpectError(beam("beam_angle = 0, lumens = 10"), lid_line,
              {"luminaire 'u' lid", "beam_angle must be a number in (0, 180), got 0"});
  ExpectError(beam("beam_angle = 180, lumens = 10"), lid_line, {"beam_angle must be a number in (0, 180)"});
  ExpectError(beam("lumens = 10"), lid_line, {"missing key 'beam_angle'"});
  ExpectError(beam("beam_angle = 20, field_angle = 15, lumens = 10"), lid_line,
              {"field_angle (full angle at 10 % of peak) must be in (beam_angle, 4 x beam_angle] = "
               "(20, 80] degrees, got 15"});
  ExpectError(beam("beam_angle = 20, field_angle = 81, lumens = 10"), lid_line, {"(20, 80]"});
  ExpectError(beam("beam_angle = 20"), lid_line, {"exactly one of lumens or peak_cd"});
  ExpectError(beam("beam_angle = 20, lumens = 10, peak_cd = 5"), lid_line,
              {"exactly one of lumens or peak_cd"});
  ExpectError(beam("beam_angle = 20, lumens = -1"), lid_line, {"lumens must be a number in (0, "});
  ExpectError(beam("beam_angle = 20, lumens = 10, zoom = [0, 30]"), lid_line,
              {"zoom min must be a number in (0, 180), got 0"});
  ExpectError(beam("beam_angle = 20, lumens = 10, zoom = [10, 180]"), lid_line,
              {"zoom max must be a number in (0, 180), got 180"});
  ExpectError(beam("beam_angle = 20, lumens = 10, zoom = [30, 10]"), lid_line,
              {"zoom must be [min_deg, max_deg] with min < max"});
  ExpectError(beam("beam_angle = 20, lumens = 10, zoom = [10]"), lid_line,
              {"zoom must be [min_deg, max_deg]"});
  ExpectError(beam("beam_angle = 20, lumens = 10, zoom = [25, 40]"), lid_line,
              {"beam_angle 20 is outside the zoom range [25, 40]"});
  ExpectError(beam("beam_angle = 20, lumens = 4e9, zoom = [1, 40]"), lid_line,
              {"the peak at the narrowest beam angle (1 degrees) is", "above 2^31 cd"});
  ExpectError(beam("beam_angle = 20, lumens = 10, zoom_range = [1, 40]"), lid_line,
              {"unknown key 'zoom_range'"});
}

TEST_F(SceneFiles, DuplicateAndBadLuminaireNames) {
  const std::string lum =
      "position = [0, 0, 2]\nmounting = \"hanging\"\n"
      "lid = { type = \"isotropic\", peak_cd = 10 }\n";
  ExpectError(Header() + Floor() + "[[luminaire]]\nname = \"a\"\n" + lum +
                  "[[luminaire]]\nname = \"a\"\n" + lum,
              kHeaderLines + 4 + 5 + 2,
              {"luminaire 'a'",
               "already used by the luminaire at line " + std::to_string(kHeaderLines + 5)});
  ExpectError(Header() + Floor() + "[[luminaire]]\nname = \"spot 1\"\n" + lum, kHeaderLines + 4 + 2,
              {"name must be a non-empty name of letters, digits, '_' and '-', got \"spot 1\""});
  ExpectError(
      Header() + Floor() + "[[luminaire]]\nname = \"a\"\n" + lum + "aim_at = [1, 0, 0]\ntilt = 3\n",
      kHeaderLines + 4 + 6, {"either aim_at or pan/tilt"});
  ExpectError(Header() + Floor() + "[[luminaire]]\nname = \"a\"\n" + lum + "mounting_ = 1\n",
              kHeaderLines + 4 + 6, {"unknown key 'mounting_'"});
  ExpectError(Header() + Floor() + Floor(), kHeaderLines + 4 + 2,
              {"quad 'floor'",
               "name already used by the object at line " + std::to_string(kHeaderLines + 1)});
}

TEST_F(SceneFiles, BadGrid) {
  ExpectError(Header() + Floor() +
                  "[[grid]]\nname = \"g\"\norigin = [0, 0, 0]\nu = [1, 0, 0]\n"
                  "v = [2, 0, 0]\ncolumns = 2\nrows = 2\n",
              kHeaderLines + 4 + 5, {"grid 'g'", "u and v must not be parallel"});
  ExpectError(Header() + Floor() +
                  "[[grid]]\nname = \"g\"\norigin = [0, 0, 0]\nu = [1, 0, 0]\n"
                  "v = [0, 1, 0]\ncolumns = 0\nrows = 2\n",
              kHeaderLines + 4 + 6, {"columns must be an integer 1..1000000, got 0"});
  ExpectError(Header() + Floor() + "[[grid]]\nname = \"g\"\npoints = [[0, 0, 0]]\n",
              kHeaderLines + 4 + 1, {"missing key 'normal'"});
}

TEST_F(SceneFiles, BadObjFaceIndex) {
  Write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 9\n");
  ExpectError(Header() + "[[mesh]]\nfile = \"m.obj\"\nmaterial = \"grey\"\n", 5,
              {"'9'", "vertex index 9 is out of range (3 vertices defined so far"}, "m.obj");
  Write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
  ExpectError(Header() + "[[mesh]]\nfile = \"m.obj\"\nmaterial = \"grey\"\n", 4,
              {"vertex index 0 is out of range", "indices start at 1"}, "m.obj");
  Write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//1\n");
  ExpectError(Header() + "[[mesh]]\nfile = \"m.obj\"\nmaterial = \"grey\"\n", 5,
              {"normal index 2 is out of range (1 normal defined"}, "m.obj");
  Write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n");
  ExpectError(Header() + "[[mesh]]\nfile = \"m.obj\"\nmaterial = \"grey\"\n", 4,
              {"vertex index -4 is out of range"}, "m.obj");
  Write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/x\n");
  ExpectError(Header() + "[[mesh]]\nfile = \"m.obj\"\nmaterial = \"grey\"\n", 4,
              {"'x' is not an integer index"}, "m.obj");
  Write("m.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
  ExpectError(Header() + "[[mesh]]\nfile = \"m.obj\"\nmaterial = \"grey\"\n", 4,
              {"face degenerate"}, "m.obj");
}

TEST_F(SceneFiles, MissingObjAndMtl) {
  ExpectError(Header() + "[[mesh]]\nfile = \"gone.obj\"\n", kHeaderLines + 2,
              {"mesh 'gone.obj'", "cannot open OBJ file", "gone.obj"});
  Write("m.obj", "# c\nmtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  ExpectError(Header() + "[[mesh]]\nfile = \"m.obj\"\n", 2,
              {"cannot open material library", "gone.mtl"}, "m.obj");
  Write("m.mtl", "newmtl a\nKd 0.2 0.2 0.2\n");
  Write("m.obj", "mtllib m.mtl\nusemtl b\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  ExpectError(Header() + "[[mesh]]\nfile = \"m.obj\"\n", 2, {"usemtl 'b'", "no such material"},
              "m.obj");
  Write("m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  ExpectError(Header() + "[[mesh]]\nfile = \"m.obj\"\n", 5, {"face has no material"}, "m.obj");
  Write("m.mtl", "newmtl a\nKd 0.2 1.0 0.2\n");
  ExpectError(Header() + "[[mesh]]\nfile = \"m.obj\"\n", 2, {"Kd must be", "[0, 1)", "'1.0'"},
              "m.mtl");
  Write("m.mtl", "newmtl a\nNs 10\n");
  ExpectError(Header() + "[[mesh]]\nfile = \"m.obj\"\n", 1, {"material 'a' has no Kd"}, "m.mtl");
}

// --- Lid::Evaluate -----------------------------------------------------------

TEST(Lid, IsotropicIsConstant) {
  Lid lid;
  lid.kind = LidKind::kIsotropic;
  lid.peak_cd = 123.0;
  for (double g : {0.0, 45.0, 90.0, 179.0, 180.0}) EXPECT_EQ(lid.Evaluate(g), 123.0);
}

TEST(Lid, CosPowerFollowsDobashiEq11) {
  Lid lid;
  lid.kind = LidKind::kCosPower;
  lid.peak_cd = 200.0;
  lid.exponent = 10.0;
  lid.spread_deg = 40.0;
  for (double g = 0; g <= 40.0; g += 2.5) {
    EXPECT_NEAR(lid.Evaluate(g), 200.0 * std::pow(std::cos(g * kPi / 180), 10.0), 1e-12) << g;
    EXPECT_EQ(lid.Evaluate(-g), lid.Evaluate(g));
  }
  EXPECT_EQ(lid.Evaluate(40.001), 0.0);
  EXPECT_EQ(lid.Evaluate(120.0), 0.0);
  // A spread past 90 degrees: no light behind the fixture, never negative.
  lid.spread_deg = 180.0;
  lid.exponent = 1.5;
  EXPECT_NEAR(lid.Evaluate(60.0), 200.0 * std::pow(0.5, 1.5), 1e-12);
  EXPECT_EQ(lid.Evaluate(135.0), 0.0);
}

TEST(Lid, TableInterpolatesLinearlyAndEndsAtLastPoint) {
  Lid lid;
  lid.kind = LidKind::kTable;
  lid.gamma_deg = {0, 10, 30, 60};
  lid.candela = {100, 80, 20, 4};
  for (size_t i = 0; i < lid.gamma_deg.size(); ++i) {
    EXPECT_EQ(lid.Evaluate(lid.gamma_deg[i]), lid.candela[i]);
  }
  EXPECT_NEAR(lid.Evaluate(5), 90.0, 1e-12);
  EXPECT_NEAR(lid.Evaluate(25), 80.0 + (20.0 - 80.0) * 0.75, 1e-12);
  EXPECT_NEAR(lid.Evaluate(50), 20.0 + (4.0 - 20.0) * (20.0 / 30.0), 1e-12);
  EXPECT_EQ(lid.Evaluate(60.0001), 0.0);
  EXPECT_EQ(lid.Evaluate(180), 0.0);
}

// --- pan/tilt convention (runtime/bake/include/relight/bake/bake.h) -----------------------

TEST(Aim, BeamAxisFollowsMountingConvention) {
  for (MountingKind m : {MountingKind::kHanging, MountingKind::kStanding}) {
    const double rest_z = m == MountingKind::kHanging ? -1.0 : 1.0;
    const Vec3 rest = BeamAxis(m, 77.0, 0.0);
    EXPECT_NEAR(rest[0], 0.0, 1e-15);
    EXPECT_NEAR(rest[1], 0.0, 1e-15);
    EXPECT_EQ(rest[2], rest_z);
    // Tilt turns towards +x of the panned frame; pan 90 turns +x into +y.
    const Vec3 side = BeamAxis(m, 90.0, 90.0);
    EXPECT_NEAR(side[0], 0.0, 1e-15);
    EXPECT_NEAR(side[1], 1.0, 1e-15);
    EXPECT_NEAR(side[2], 0.0, 1e-15);
    const Vec3 a = BeamAxis(m, 30.0, 60.0);
    const double t = 60 * kPi / 180, p = 30 * kPi / 180;
    EXPECT_NEAR(a[0], std::sin(t) * std::cos(p), 1e-15);
    EXPECT_NEAR(a[1], std::sin(t) * std::sin(p), 1e-15);
    EXPECT_NEAR(a[2], rest_z * std::cos(t), 1e-15);
  }
}

TEST(Aim, AimAtInvertsBeamAxis) {
  const Vec3 position{1.0, -2.0, 2.5};
  for (MountingKind m : {MountingKind::kHanging, MountingKind::kStanding}) {
    for (double tilt = 1.0; tilt < 180.0; tilt += 7.0) {
      for (double pan = -179.0; pan <= 180.0; pan += 11.0) {
        const Vec3 axis = BeamAxis(m, pan, tilt);
        const Vec3 target{position[0] + 3 * axis[0], position[1] + 3 * axis[1],
                          position[2] + 3 * axis[2]};
        double pan_out = 0, tilt_out = 0;
        AimAt(m, position, target, &pan_out, &tilt_out);
        EXPECT_NEAR(tilt_out, tilt, 1e-9);
        EXPECT_NEAR(pan_out, pan, 1e-9);
        EXPECT_GE(tilt_out, 0.0);
        EXPECT_LE(tilt_out, 180.0);
        EXPECT_GT(pan_out, -180.0);
        EXPECT_LE(pan_out, 180.0);
      }
    }
  }
}

TEST(Aim, AimAtSpecialDirections) {
  double pan = -1, tilt = -1;
  AimAt(MountingKind::kHanging, {0, 0, 3}, {0, 0, 0}, &pan, &tilt);  // straight down
  EXPECT_EQ(pan, 0.0);
  EXPECT_EQ(tilt, 0.0);
  AimAt(MountingKind::kHanging, {0, 0, 3}, {0, 0, 5}, &pan, &tilt);  // straight up
  EXPECT_EQ(pan, 0.0);
  EXPECT_NEAR(tilt, 180.0, 1e-12);
  AimAt(MountingKind::kStanding, {0, 0, 0}, {0, 0, 5}, &pan, &tilt);
  EXPECT_EQ(pan, 0.0);
  EXPECT_EQ(tilt, 0.0);
  AimAt(MountingKind::kStanding, {0, 0, 0}, {-2, 0, 0}, &pan,
        &tilt);  // along -x: pan 180, not -180
  EXPECT_EQ(pan, 180.0);
  EXPECT_NEAR(tilt, 90.0, 1e-12);
  AimAt(MountingKind::kStanding, {0, 0, 0}, {-2, -0.0, 0}, &pan, &tilt);
  EXPECT_EQ(pan, 180.0);
}

}  // namespace
}  // namespace relight::baker
