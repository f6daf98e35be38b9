// Photometric files: every fixture in fixtures/photometry/ and every real
// manufacturer's file in ../shared/photometry/ parses to what it holds; each
// malformed variant is an error naming the file, the line and what was
// expected; symmetry folding, the full-circle expansion and the flux hold
// against independent computations.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "relight/baker/analytic_photometry.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/scene.h"

namespace relight::baker {
namespace {

constexpr double kPi = 3.14159265358979323846;

std::string FixtureDir() { return std::string(RELIGHT_SOURCE_DIR) + "/fixtures/photometry/"; }
std::string SharedDir() { return std::string(RELIGHT_SHARED_DIR) + "/photometry/"; }
bool Exists(const std::string& path) {
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}
std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Values a fixture was sampled from, rounded as the fixture rounds them.
double Sampled(const std::string& kind, double c, double g) {
  return std::round(AnalyticCandela(kind, c, g) * 100.0) / 100.0;
}
std::string KindOf(const PhotometricTable& t) {
  return t.luminaire.substr(t.luminaire.rfind(' ') + 1);
}

TEST(PhotometricFixtures, CommittedFilesAreWhatTheGeneratorWrites) {
  // `relight-lid fixtures fixtures/photometry` regenerates them.
  for (const PhotometricFixture& f : PhotometricFixtures()) {
    EXPECT_EQ(ReadText(FixtureDir() + f.file_name), f.text) << f.file_name << " is stale";
  }
  for (const MalformedFixture& f : MalformedPhotometricFixtures()) {
    EXPECT_EQ(ReadText(FixtureDir() + "malformed/" + f.file_name), f.text) << f.file_name;
  }
}

TEST(PhotometricFixtures, EveryFixtureParsesToItsAnalyticSamples) {
  const std::vector<PhotometricFixture> fixtures = PhotometricFixtures();
  ASSERT_EQ(fixtures.size(), 11u);
  for (const PhotometricFixture& f : fixtures) {
    SCOPED_TRACE(f.file_name);
    const PhotometricTable t = LoadPhotometricFile(FixtureDir() + f.file_name);
    EXPECT_EQ(t.version, f.table.version);
    EXPECT_EQ(t.symmetry, f.table.symmetry);
    EXPECT_EQ(t.c_deg, f.table.c_deg);
    EXPECT_EQ(t.gamma_deg, f.table.gamma_deg);
    EXPECT_EQ(t.tilt_data.angle_deg, f.table.tilt_data.angle_deg);
    EXPECT_EQ(t.tilt_data.factor, f.table.tilt_data.factor);
    ASSERT_EQ(t.candela.size(), t.planes() * t.gammas());
    const std::string kind = KindOf(t);
    double worst = 0;
    for (size_t p = 0; p < t.planes(); ++p) {
      for (size_t g = 0; g < t.gammas(); ++g) {
        worst = std::max(worst, std::abs(t.At(p, g) - Sampled(kind, t.c_deg[p], t.gamma_deg[g])));
      }
    }
    // EULUMDAT stores cd/klm with 9 digits: a relative 1e-9 at most.
    EXPECT_LE(worst, 1e-6 * t.PeakCandela());
  }
}

TEST(PhotometricFixtures, VersionsSymmetriesAndTiltAreRecognised) {
  struct Case {
    const char* file;
    const char* version;
    CSymmetry symmetry;
    const char* tilt;
  };
  const Case cases[] = {
      {"ies_1986_axial.ies", "LM-63-1986", CSymmetry::kAxial, "NONE"},
      {"ies_1991_quadrant.ies", "LM-63-1991", CSymmetry::kQuadrant, "NONE"},
      {"ies_1995_bilateral.ies", "LM-63-1995", CSymmetry::kBilateral, "NONE"},
      {"ies_2002_bilateral90.ies", "LM-63-2002", CSymmetry::kBilateral90, "NONE"},
      {"ies_2002_tilt_include.ies", "LM-63-2002", CSymmetry::kQuadrant, "INCLUDE"},
      {"ies_2019_full.ies", "LM-63-2019", CSymmetry::kNone, "NONE"},
      {"ldt_isym0_none.ldt", "EULUMDAT", CSymmetry::kNone, "NONE"},
      {"ldt_isym1_axial.ldt", "EULUMDAT", CSymmetry::kAxial, "NONE"},
      {"ldt_isym2_c0_c180.ldt", "EULUMDAT", CSymmetry::kBilateral, "NONE"},
      {"ldt_isym3_c90_c270.ldt", "EULUMDAT", CSymmetry::kBilateral90, "NONE"},
      {"ldt_isym4_quadrant.ldt", "EULUMDAT", CSymmetry::kQuadrant, "NONE"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const PhotometricTable t = LoadPhotometricFile(FixtureDir() + c.file);
    EXPECT_EQ(t.version, c.version);
    EXPECT_EQ(t.symmetry, c.symmetry);
    EXPECT_EQ(t.tilt, c.tilt);
  }
  // The 1995 fixture carries a candela multiplier of 2: the file holds half.
  const PhotometricTable wash = LoadPhotometricFile(FixtureDir() + "ies_1995_bilateral.ies");
  EXPECT_EQ(wash.multiplier, 2.0);
  EXPECT_NEAR(wash.At(0, 0), Sampled("wallwash", 0, 0), 1e-9);
}

TEST(PhotometricFixtures, MalformedVariantsNameFileLineAndWhatWasExpected) {
  const std::vector<MalformedFixture> malformed = MalformedPhotometricFixtures();
  ASSERT_GE(malformed.size(), 12u);
  for (const MalformedFixture& f : malformed) {
    SCOPED_TRACE(f.file_name);
    const std::string path = FixtureDir() + "malformed/" + f.file_name;
    try {
      LoadPhotometricFile(path);
      ADD_FAILURE() << "accepted";
    } catch (const SceneError& e) {
      const std::string what = e.what();
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(what.rfind(path + ":", 0), 0u) << what;
      EXPECT_NE(what.find(f.expect), std::string::npos) << what;
      EXPECT_GT(e.line(), 0) << what;
      if (f.line > 0) {
        EXPECT_EQ(e.line(), f.line) << what;
      }
      std::printf("  %s\n", what.c_str() + FixtureDir().size());
    }
  }
}

TEST(PhotometricFixtures, OtherBadInputIsAClearError) {
  const auto expect_error = [](const std::string& text, bool ies, const std::string& part) {
    try {
      if (ies) {
        ParseIes(text, "x.ies");
      } else {
        ParseEulumdat(text, "x.ldt");
      }
      ADD_FAILURE() << "accepted: " << part;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  };
  const std::string head = "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 5\n";
  expect_error("", true, "empty file");
  expect_error(head + "0 45 90\n0\n10 5 0\n7\n", true, "1 unexpected value(s) from '7'");
  expect_error(head + "0 45 90\n0\n10 -5 0\n", true, "is negative");
  expect_error(head + "0 45 90\n0\n0 0 0\n", true, "emits no light");
  expect_error(head + "0 45 45\n0\n10 5 0\n", true, "vertical angles must increase strictly");
  expect_error(head + "0 45 190\n0\n10 5 0\n", true, "expected an angle in [0, 180]");
  expect_error("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 2 1 2 0 0 0\n1 1 5\n0 45 90\n0 45\n1 1 1 1 1 1\n",
               true, "horizontal angles run from 0 to 45");
  expect_error("IESNA:LM-63-2002\nTILT=NONE\n1 1000 0 3 1 1 2 0 0 0\n", true, "candela multiplier must be > 0");
  expect_error("IESNA:LM-63-2002\nTILT=\n", true, "TILT= has no value");
  expect_error("IESNA:LM-63-2002\nTILT=INCLUDE\n1 2 0 90 1\n", true,
               "TILT angle count 2 (angles and factors) on line 3 declares 4 values, but the file "
               "ends after 3");
  // Issue 17: counts are bounded, and checked against the values present,
  // before anything is sized from them.
  expect_error("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 10001 1 1 2 0 0 0\n", true,
               "number of vertical angles (an integer 1..10000), got 10001");
  expect_error("IESNA:LM-63-2002\nTILT=INCLUDE\n1 10000 0 90 1 1\n", true,
               "TILT angle count 10000 (angles and factors) on line 3 declares 20000 values");
  {
    std::string big = "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2000 1000 1 2 0 0 0\n1 1 5\n";
    char buf[32];
    for (int i = 0; i < 2000; ++i) {
      std::snprintf(buf, sizeof buf, "%.10g ", i * 0.09);
      big += buf;
    }
    for (int i = 0; i < 1000; ++i) {
      std::snprintf(buf, sizeof buf, "%.10g ", i * 360.0 / 999);
      big += buf;
    }
    expect_error(big, true,
                 "x.ies:3: 2000 vertical x 1000 horizontal angles make 2000000 candela values, more "
                 "than the limit of 1000000");
  }
  expect_error("company\n1\n2\n10001\n", false, "number of C planes Mc (an integer 1..10000)");
  expect_error("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3.5 1 1 2 0 0 0\n", true,
               "number of vertical angles (an integer");
  expect_error("company\n1\n", false, "symmetry indicator Isym (0-4) on line 3, but the file ends");
  try {
    LoadPhotometricFile(FixtureDir() + "no_such_file.ies");
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot read the photometric file"), std::string::npos);
  }
  try {
    LoadPhotometricFile(FixtureDir() + "../living_room.toml");
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("expected .ies or .ldt"), std::string::npos);
  }
}

TEST(PhotometricFixtures, DecimalCommasAndLineEndsOfTheWild) {
  const PhotometricFixture f = PhotometricFixtures()[8];  // EULUMDAT Isym 2, CRLF
  std::string commas = f.text;
  for (char& c : commas) c = c == '.' ? ',' : c;
  std::string lf;
  for (char c : f.text) {
    if (c != '\r') lf += c;
  }
  const PhotometricTable a = ParseEulumdat(f.text, "a.ldt");
  const PhotometricTable b = ParseEulumdat(commas, "b.ldt");
  const PhotometricTable c = ParseEulumdat(lf, "c.ldt");
  EXPECT_EQ(a.candela, b.candela);
  EXPECT_EQ(a.candela, c.candela);
  // IES values separated by commas and CR-only line ends read the same.
  const PhotometricFixture g = PhotometricFixtures()[3];
  std::string ies_commas = g.text;
  const size_t data = ies_commas.find("TILT=NONE");
  for (size_t i = data; i < ies_commas.size(); ++i) {
    if (ies_commas[i] == ' ') ies_commas[i] = ',';
    if (ies_commas[i] == '\n') ies_commas[i] = '\r';
  }
  EXPECT_EQ(ParseIes(ies_commas, "x.ies").candela, ParseIes(g.text, "y.ies").candela);
}

TEST(PhotometricFixtures, WritersRoundTripEveryVersionAndSymmetry) {
  for (const PhotometricFixture& f : PhotometricFixtures()) {
    SCOPED_TRACE(f.file_name);
    const PhotometricTable t = f.version == "EULUMDAT" ? ParseEulumdat(f.text, f.file_name)
                                                       : ParseIes(f.text, f.file_name);
    if (f.version != "EULUMDAT") {
      for (const char* v : {"LM-63-1986", "LM-63-1991", "LM-63-1995", "LM-63-2002", "LM-63-2019"}) {
        const PhotometricTable again = ParseIes(WriteIes(t, v), "again.ies");
        EXPECT_EQ(again.version, v);
        EXPECT_EQ(again.c_deg, t.c_deg);
        for (size_t i = 0; i < t.candela.size(); ++i) {
          ASSERT_NEAR(again.candela[i], t.candela[i], 1e-8 * t.PeakCandela());
        }
      }
    }
    if (t.symmetry != CSymmetry::kNone || t.c_deg.back() < 360) {
      const PhotometricTable again = ParseEulumdat(WriteEulumdat(t), "again.ldt");
      EXPECT_EQ(again.symmetry, t.symmetry);
      EXPECT_EQ(again.c_deg, t.c_deg);
      for (size_t i = 0; i < t.candela.size(); ++i) {
        ASSERT_NEAR(again.candela[i], t.candela[i], 1e-8 * t.PeakCandela());
      }
    }
  }
}

// Mirror images of a direction have one intensity; the expansion to the full
// circle interpolates exactly like the folded table.
TEST(PhotometricFixtures, SymmetryFoldingAndFullCircleExpansion) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> c_dist(0, 360), g_dist(0, 180);
  for (const PhotometricFixture& f : PhotometricFixtures()) {
    SCOPED_TRACE(f.file_name);
    const PhotometricTable& t = f.table;
    const FullCircleTable full = ExpandToFullCircle(t);
    EXPECT_EQ(full.c_deg.front(), 0.0);
    EXPECT_EQ(full.c_deg.back(), 360.0);
    for (int i = 0; i < 500; ++i) {
      const double c = c_dist(rng), g = g_dist(rng);
      const double v = t.Evaluate(c, g);
      ASSERT_NEAR(full.Evaluate(c, g), v, 1e-9 * t.PeakCandela()) << c << " " << g;
      switch (t.symmetry) {
        case CSymmetry::kAxial:
          ASSERT_NEAR(t.Evaluate(c + 77, g), v, 1e-9);
          break;
        case CSymmetry::kQuadrant:
          ASSERT_NEAR(t.Evaluate(180 - c, g), v, 1e-9);
          ASSERT_NEAR(t.Evaluate(360 - c, g), v, 1e-9);
          break;
        case CSymmetry::kBilateral:
          ASSERT_NEAR(t.Evaluate(360 - c, g), v, 1e-9);
          break;
        case CSymmetry::kBilateral90:
          ASSERT_NEAR(t.Evaluate(180 - c, g), v, 1e-9);
          break;
        case CSymmetry::kNone:
          break;
      }
      // gamma past 180 is the opposite plane.
      ASSERT_NEAR(t.Evaluate(c + 180, 360 - g), v, 1e-9 * t.PeakCandela());
    }
    // Between knots the table is close to the function it samples.
    const std::string kind = KindOf(t);
    double worst = 0;
    for (int i = 0; i < 500; ++i) {
      const double c = c_dist(rng), g = g_dist(rng);
      if (g > t.gamma_deg.back()) continue;
      worst = std::max(worst, std::abs(t.Evaluate(c, g) - AnalyticCandela(kind, c, g)));
    }
    EXPECT_LE(worst, 0.05 * t.PeakCandela());
  }
}

TEST(PhotometricFixtures, FluxMatchesClosedForm) {
  // 1200 cos^4 down + 40 cos up: 2 pi (1200 / 5 + 40 / 2) lm.
  const PhotometricTable axial = LoadPhotometricFile(FixtureDir() + "ies_1986_axial.ies");
  const double exact = 2 * kPi * (1200.0 / 5 + 40.0 / 2);
  EXPECT_NEAR(axial.LuminousFlux(), exact, 0.002 * exact);
  std::printf("axial fixture: flux %.2f lm, closed form %.2f lm\n", axial.LuminousFlux(), exact);
}

// The real manufacturers' files (../shared/photometry/SOURCES.md).
class RealPhotometricFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!Exists(SharedDir() + "SOURCES.md")) {
      GTEST_SKIP() << "../shared/photometry/ is absent: the real photometric files live beside the "
                      "clone (" << SharedDir() << ")";
    }
  }
};

TEST_F(RealPhotometricFiles, EveryFileParsesAsSourcesMdDescribesIt) {
  struct Case {
    const char* file;
    const char* version;
    CSymmetry symmetry;
    size_t planes, gammas;
    double peak_cd, flux_lm;  // flux: SOURCES.md's independent integral; 0 = not given
  };
  const Case cases[] = {
      {"rab_dled6r8y_downlight.ies", "LM-63-2002", CSymmetry::kAxial, 1, 37, 269, 532.0},
      {"rab_bayled78_highbay_c0-180.ies", "LM-63-2002", CSymmetry::kBilateral, 9, 73, 0, 5821.8},
      {"luxion_br8060_40d_spot.ies", "LM-63-2002", CSymmetry::kNone, 9, 181, 3116, 1052},
      {"maxwell8_t4_lm63-1995_asym.ies", "LM-63-1995", CSymmetry::kNone, 73, 91, 425, 999.9},
      {"ledalite_251602_lm63-1995.ies", "LM-63-1995", CSymmetry::kQuadrant, 5, 73, 0, 5297},
      {"ledvance_flmaxlum900w_asym50x110.ldt", "EULUMDAT", CSymmetry::kNone, 8, 19, 0, 0},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const PhotometricTable t = LoadPhotometricFile(SharedDir() + c.file);
    EXPECT_EQ(t.version, c.version);
    EXPECT_EQ(t.symmetry, c.symmetry);
    EXPECT_EQ(t.planes(), c.planes);
    EXPECT_EQ(t.gammas(), c.gammas);
    if (c.peak_cd > 0) {
      EXPECT_NEAR(t.PeakCandela(), c.peak_cd, 0.5);
    }
    if (c.flux_lm > 0) {
      EXPECT_NEAR(t.LuminousFlux(), c.flux_lm, 0.005 * c.flux_lm);
    }
    std::printf("  %-40s %-10s %-22s %3zu x %3zu  peak %9.1f cd  flux %8.1f lm\n", c.file,
                t.version.c_str(), CSymmetryName(t.symmetry), t.planes(), t.gammas(),
                t.PeakCandela(), t.LuminousFlux());
  }
  // The high bay's candela multiplier 0.9687 is applied.
  const PhotometricTable bay = LoadPhotometricFile(SharedDir() + "rab_bayled78_highbay_c0-180.ies");
  EXPECT_DOUBLE_EQ(bay.multiplier, 0.9687);
  // EULUMDAT cd/klm scaled by the 123000 lm lamp flux.
  const PhotometricTable flood = LoadPhotometricFile(SharedDir() + "ledvance_flmaxlum900w_asym50x110.ldt");
  EXPECT_NEAR(flood.At(0, 0), 224.77 * 123.0, 1e-6);
  EXPECT_EQ(flood.lamp_lumens, 123000.0);
}

// Scene files name photometric files relative to themselves.
TEST(PhotometricFixtures, SceneLidFromFile) {
  std::string dir = ::testing::TempDir() + "relight_lid_XXXXXX";
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  const std::string scene_text =
      "[scene]\nname = \"t\"\n[camera]\nposition = [1, 1, 1]\ntarget = [0, 0, 0]\nfov = 50\n"
      "[[quad]]\nname = \"floor\"\ncorners = [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]\nreflectance = 0.5\n"
      "[[luminaire]]\nname = \"a\"\nposition = [0.5, 0.5, 2]\nmounting = \"hanging\"\n"
      "lid = { type = \"file\", path = \"" + FixtureDir() + "ies_1986_axial.ies\" }\n"
      "[[luminaire]]\nname = \"b\"\nposition = [0.5, 0.5, 2]\nmounting = \"wall\"\nroll = 30\n"
      "yaw = 90\nlid = { type = \"file\", path = \"" + FixtureDir() + "ies_2019_full.ies\" }\n";
  std::ofstream(dir + "/s.toml") << scene_text;
  const Scene scene = LoadScene(dir + "/s.toml");
  ASSERT_EQ(scene.luminaires.size(), 2u);
  EXPECT_EQ(scene.luminaires[0].lid.kind, LidKind::kTable);  // one C plane: axisymmetric
  EXPECT_NEAR(scene.luminaires[0].lid.Evaluate(10.0), Sampled("axial", 0, 10), 1e-9);
  EXPECT_EQ(scene.luminaires[1].lid.kind, LidKind::kCGamma);
  EXPECT_EQ(scene.luminaires[1].mounting, MountingKind::kWall);
  EXPECT_EQ(scene.luminaires[1].roll_deg, 30.0);
  EXPECT_EQ(scene.luminaires[1].yaw_deg, 90.0);
  EXPECT_NEAR(scene.luminaires[1].lid.Evaluate(200.0, 60.0), Sampled("asym", 200, 60), 1e-9);

  // A bad file: the scene's line and the photometric file's line and problem.
  std::ofstream(dir + "/bad.toml")
      << "[scene]\nname = \"t\"\n[camera]\nposition = [1, 1, 1]\ntarget = [0, 0, 0]\nfov = 50\n"
         "[[quad]]\nname = \"floor\"\ncorners = [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]\nreflectance = 0.5\n"
         "[[luminaire]]\nname = \"a\"\nposition = [0.5, 0.5, 2]\nmounting = \"hanging\"\n"
         "lid = { type = \"file\", path = \"" + FixtureDir() + "malformed/ies_truncated.ies\" }\n";
  try {
    LoadScene(dir + "/bad.toml");
    ADD_FAILURE();
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.line(), 15) << what;
    EXPECT_NE(what.find("ies_truncated.ies:"), std::string::npos) << what;
    EXPECT_NE(what.find("but the file ends"), std::string::npos) << what;
  }
  std::system(("rm -rf '" + dir + "'").c_str());
}

}  // namespace
}  // namespace relight::baker
