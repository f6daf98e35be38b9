// Real luminaires end to end: each manufacturer's file in ../shared/photometry/
// hangs 3 m above a floor; the baker writes a bake file, the fixed-point
// engine reads it and lights a floor grid at several aims (and rolls). Its
// direct illuminance must match a plain inverse-square computation from the
// file's own table (the parsed PhotometricTable, bilinear in the file's angles)
// in a fixture frame built independently (axis-angle rotations), within 1 %
// of the grid's peak.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "relight/bake/bake.h"
#include "relight/baker/accuracy.h"
#include "relight/baker/baker.h"
#include "relight/baker/lid_error.h"
#include "relight/baker/photometric_file.h"
#include "relight/engine/engine.h"

namespace relight::test {
namespace {

using baker::Vec3;

constexpr double kPi = 3.14159265358979323846;
constexpr double kHeight = 3.0;
constexpr double kHalf = 10.0;  // floor and grid: 20 m x 20 m
constexpr int kGrid = 41;

std::string SharedFile(const std::string& name) {
  return std::string(RELIGHT_SHARED_DIR) + "/photometry/" + name;
}
std::string FixtureFile(const std::string& name) {
  return std::string(RELIGHT_SOURCE_DIR) + "/fixtures/photometry/" + name;
}
bool Exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

// Rodrigues: v turned by `deg` about unit `k` (right hand).
Vec3 Turn(const Vec3& v, const Vec3& k, double deg) {
  const double a = deg * kPi / 180, c = std::cos(a), s = std::sin(a);
  const double kv = k[0] * v[0] + k[1] * v[1] + k[2] * v[2];
  const Vec3 kxv{k[1] * v[2] - k[2] * v[1], k[2] * v[0] - k[0] * v[2], k[0] * v[1] - k[1] * v[0]};
  Vec3 out;
  for (int i = 0; i < 3; ++i) out[i] = v[i] * c + kxv[i] * s + k[i] * kv * (1 - c);
  return out;
}

// A hanging fixture's frame, built as the physical motion: at rest C0 = +x,
// C90 = +y, beam -z; roll about the beam's back (+z) by `roll` (C0 towards
// C90), tilt about +y so the beam swings towards +x, pan about +z.
struct Frame {
  Vec3 c0{1, 0, 0}, c90{0, 1, 0}, axis{0, 0, -1};
};
Frame HangingFrame(double pan, double tilt, double roll) {
  Frame f;
  for (Vec3* v : {&f.c0, &f.c90, &f.axis}) {
    *v = Turn(*v, {0, 0, 1}, roll);
    *v = Turn(*v, {0, 1, 0}, -tilt);
    *v = Turn(*v, {0, 0, 1}, pan);
  }
  return f;
}

double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// E = I(C, gamma) cos(theta) / d^2 on the floor point p, from the file's own table.
double DirectLux(const baker::PhotometricTable& table, const Frame& f, const Vec3& lum,
                 const Vec3& p) {
  const Vec3 d{p[0] - lum[0], p[1] - lum[1], p[2] - lum[2]};
  const double d2 = Dot(d, d), len = std::sqrt(d2);
  const Vec3 u{d[0] / len, d[1] / len, d[2] / len};
  const double gamma = std::acos(std::clamp(Dot(u, f.axis), -1.0, 1.0)) * 180 / kPi;
  double c = std::atan2(Dot(u, f.c90), Dot(u, f.c0)) * 180 / kPi;
  if (c < 0) c += 360;
  return table.Evaluate(c, gamma) * (-u[2]) / d2;  // floor normal +z
}

baker::Scene FloorScene(const std::string& lid_path, int sh_degree) {
  baker::Scene s;
  s.name = "floor";
  s.path = "real_luminaire_test";
  s.patch_size_m = 2.0;
  baker::Surface floor;
  floor.name = "floor";
  floor.corners = {{-kHalf, -kHalf, 0}, {kHalf, -kHalf, 0}, {kHalf, kHalf, 0}, {-kHalf, kHalf, 0}};
  floor.reflectance = {0.3, 0.3, 0.3};
  s.surfaces.push_back(floor);
  baker::Luminaire lum;
  lum.name = "lum";
  lum.position = {0, 0, kHeight};
  lum.sh_degree = sh_degree;
  lum.lid = baker::LoadLid(lid_path);
  s.luminaires.push_back(lum);
  baker::CalcGrid grid;
  grid.name = "floor";
  grid.columns = grid.rows = kGrid;
  for (int r = 0; r < kGrid; ++r) {
    for (int c = 0; c < kGrid; ++c) {
      const double x = -kHalf + 2 * kHalf * c / (kGrid - 1), y = -kHalf + 2 * kHalf * r / (kGrid - 1);
      grid.points.push_back({x * 0.98, y * 0.98, 0.001});
      grid.normals.push_back({0, 0, 1});
    }
  }
  s.grids.push_back(grid);
  s.camera.position = {0, -8, 4};
  s.camera.target = {0, 0, 0};
  return s;
}

struct Aim {
  const char* label;
  double pan, tilt, roll;
};

// Bakes the floor scene for `file`, opens the bake file in the engine and
// checks every aim; prints one table row per aim.
void CheckFile(const std::string& path, const std::vector<Aim>& aims) {
  const baker::PhotometricTable table = baker::LoadPhotometricFile(path);
  const baker::Scene scene = FloorScene(path, 2);
  baker::BakeOptions options;
  options.threads = 2;
  baker::Baker b(scene, options);
  const std::string bake_path =
      ::testing::TempDir() + "real_luminaire_" + std::to_string(::getpid()) + ".rlb";
  ASSERT_TRUE(WriteBake(b.Bake(), bake_path).ok());
  Engine engine;
  ASSERT_TRUE(engine.Open(bake_path).ok());
  std::remove(bake_path.c_str());
  const std::string name = path.substr(path.find_last_of('/') + 1);
  for (const Aim& aim : aims) {
    SCOPED_TRACE(name + " " + aim.label);
    ASSERT_TRUE(engine.SetPanTilt(0, Q16_16::FromRatio(std::llround(aim.pan * 1000), 1000),
                                  Q16_16::FromRatio(std::llround(aim.tilt * 1000), 1000)).ok());
    ASSERT_TRUE(engine.SetRoll(0, Q16_16::FromRatio(std::llround(aim.roll * 1000), 1000)).ok());
    engine.Update();
    const int32_t* got = engine.grid_direct_illuminance(0).raw();
    const Frame f = HangingFrame(aim.pan, aim.tilt, aim.roll);
    const Vec3 lum = scene.luminaires[0].position;
    std::vector<double> want;
    double peak = 0;
    for (const Vec3& p : scene.grids[0].points) {
      want.push_back(DirectLux(table, f, lum, p));
      peak = std::max(peak, want.back());
    }
    ASSERT_GT(peak, 0.0);
    double worst = 0, sum = 0;
    for (size_t k = 0; k < want.size(); ++k) {
      const double e = got[3 * k] / 4096.0;
      worst = std::max(worst, std::abs(e - want[k]));
      sum += std::abs(e - want[k]);
    }
    std::printf("| %s | %s | %.1f | %.4f%% | %.5f%% |\n", name.c_str(), aim.label, peak,
                100 * worst / peak, 100 * sum / static_cast<double>(want.size()) / peak);
    EXPECT_LE(worst, 0.01 * peak);
  }
}

const std::vector<Aim>& StandardAims() {
  static const std::vector<Aim> aims = {{"straight down", 0, 0, 0},
                                        {"tilt 30", 0, 30, 0},
                                        {"pan 45, tilt 60", 45, 60, 0}};
  return aims;
}

// Rolled aims for luminaires that are not axisymmetric.
const std::vector<Aim>& RolledAims() {
  static const std::vector<Aim> aims = {{"roll 35", 0, 0, 35},
                                        {"pan -120, tilt 40, roll 70", -120, 40, 70},
                                        {"pan 200, tilt 25, roll -150", 200, 25, -150}};
  return aims;
}

const char* const kRealFiles[] = {
    "rab_dled6r8y_downlight.ies",     "rab_bayled78_highbay_c0-180.ies",
    "luxion_br8060_40d_spot.ies",     "maxwell8_t4_lm63-1995_asym.ies",
    "ledalite_251602_lm63-1995.ies",  "ledvance_flmaxlum900w_asym50x110.ldt"};

class RealLuminaires : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    if (!Exists(SharedFile(GetParam()))) {
      GTEST_SKIP() << "../shared/photometry/ is absent: the real photometric files live beside the "
                      "clone (" << SharedFile(GetParam()) << ")";
    }
  }
};

TEST_P(RealLuminaires, RuntimeDirectMatchesInverseSquareFromTheFileAtThreeAims) {
  std::vector<Aim> aims = StandardAims();
  const baker::PhotometricTable t = baker::LoadPhotometricFile(SharedFile(GetParam()));
  if (t.symmetry != baker::CSymmetry::kAxial) {
    for (const Aim& a : RolledAims()) aims.push_back(a);
  }
  CheckFile(SharedFile(GetParam()), aims);
}

INSTANTIATE_TEST_SUITE_P(Files, RealLuminaires, ::testing::ValuesIn(kRealFiles),
                         [](const ::testing::TestParamInfo<const char*>& param_info) {
                           std::string s = param_info.param;
                           s = s.substr(0, s.find('.'));
                           for (char& c : s) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                           return s;
                         });

// The project's own fixtures (no ../shared needed): every symmetry case.
TEST(FixtureLuminaires, RuntimeDirectMatchesInverseSquareFromTheFile) {
  for (const char* f : {"ies_1995_bilateral.ies", "ies_2002_bilateral90.ies", "ies_2019_full.ies",
                        "ldt_isym4_quadrant.ldt"}) {
    std::vector<Aim> aims = StandardAims();
    for (const Aim& a : RolledAims()) aims.push_back(a);
    CheckFile(FixtureFile(f), aims);
  }
}

// The living room lit by five real files (fixtures/living_room_ies.toml) at
// the SH degrees `--lid-error 2%` chooses: total light (with interreflection)
// from the engine against the float64 reference solve with the exact (C, gamma)
// LIDs. Bars: max <= 2 % of peak, mean <= 0.3 %, at the scene's aims and with
// every fixture moved.
TEST(RealLuminaires, LivingRoomAtChosenDegreesMatchesTheReference) {
  if (!Exists(SharedFile("SOURCES.md"))) {
    GTEST_SKIP() << "../shared/photometry/ is absent (" << SharedFile("") << ")";
  }
  baker::Scene scene =
      baker::LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/living_room_ies.toml");
  const std::vector<baker::LuminaireDegree> degrees =
      baker::ApplyLidErrorTarget(&scene, 0.02, baker::DirectModeKind::kExact);
  for (const baker::LuminaireDegree& d : degrees) {
    std::printf("  %-10s degree %2d, zonal flux error %.2f%%\n", d.name.c_str(), d.choice.degree,
                100 * d.choice.error);
  }
  baker::BakeOptions options;
  options.threads = 2;
  baker::Baker b(scene, options);
  const std::string bake_path =
      ::testing::TempDir() + "living_room_ies_" + std::to_string(::getpid()) + ".rlb";
  ASSERT_TRUE(WriteBake(b.Bake(), bake_path).ok());
  Engine engine;
  ASSERT_TRUE(engine.Open(bake_path).ok());
  std::remove(bake_path.c_str());
  std::vector<std::vector<baker::FixtureSetting>> cases = {b.DefaultSettings()};
  std::vector<baker::FixtureSetting> moved = b.DefaultSettings();
  for (size_t i = 0; i < moved.size(); ++i) {
    moved[i].pan_deg += 40.0 + 25.0 * static_cast<double>(i);
    moved[i].tilt_deg = 20.0 + 10.0 * static_cast<double>(i);
    moved[i].roll_deg = 30.0 * static_cast<double>(i);
  }
  cases.push_back(moved);
  for (const auto& settings : cases) {
    const baker::ReferenceResult ref = b.Reference(settings);
    const baker::AccuracyReport r = baker::CompareWithReference(&engine, ref, settings);
    std::printf("  vertices: peak %.1f cd/m2 max %.3f%% mean %.4f%%; grid: peak %.1f lux max "
                "%.3f%% mean %.4f%%\n",
                r.vertices.peak, 100 * r.vertices.max_rel, 100 * r.vertices.mean_rel, r.grids.peak,
                100 * r.grids.max_rel, 100 * r.grids.mean_rel);
    EXPECT_LE(r.grids.max_rel, 0.02);
    EXPECT_LE(r.grids.mean_rel, 0.003);
    EXPECT_LE(r.vertices.max_rel, 0.02);
    EXPECT_LE(r.vertices.mean_rel, 0.003);
  }
}

}  // namespace
}  // namespace relight::test
