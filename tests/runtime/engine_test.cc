// The engine end to end on a bake built in code: a small floor mesh and one
// calculation grid, two luminaires (one exact-direct, one all-in-SH), basis
// values from the float64 SH of a simple synthetic scene. Every output is
// compared with a float64 computation on the same data.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <string>
#include <type_traits>
#include <unistd.h>
#include <vector>

#include "engine_test_support.h"
#include "relight/baker/photometry.h"
#include "relight/bake/bake.h"
#include "relight/engine/engine.h"
#include "relight/base/sh_index.h"

#include "count_allocations.h"

namespace relight {
namespace {

using baker::MountingKind;
using testing::Vec3;

constexpr double kQ12 = 4096.0;

struct LightDef {
  std::string name;
  Vec3 position;
  DirectMode mode;
  int degree;
  double peak_cd, exponent;
  int M;
};

const LightDef kLights[2] = {
    {"spot", {1.5, 1.5, 3.0}, DirectMode::kExactDirect, 8, 2000.0, 10.0, 90},
    {"wash", {0.5, 2.5, 2.8}, DirectMode::kAllInSh, 6, 600.0, 2.0, 60},
};

// Floor points where light lands before it is reflected (the synthetic
// "indirect" is what these bounce points send to each receiver).
const Vec3 kBounce[3] = {{0.8, 0.7, 0.0}, {2.2, 1.2, 0.0}, {1.4, 2.6, 0.0}};

struct Receiver {
  Vec3 p, n;
  double rho[3];  // vertices: reflectance; grids: 1/pi x pi, i.e. lux stays lux
};

struct TestScene {
  std::vector<Receiver> sets[2];  // vertices, grid 0
  std::vector<uint16_t> albedo;
};

TestScene MakeScene() {
  TestScene s;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      Receiver r;
      r.p = {1.0 * i, 1.0 * j, 0.0};
      r.n = {0, 0, 1};
      const uint16_t a[3] = {static_cast<uint16_t>(30000 + 2000 * i),
                             static_cast<uint16_t>(25000 + 3000 * j), 20000};
      for (int c = 0; c < 3; ++c) {
        s.albedo.push_back(a[c]);
        r.rho[c] = a[c] / 65535.0;  // the data the runtime sees
      }
      s.sets[0].push_back(r);
    }
  }
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      Receiver r;
      r.p = {0.5 + i, 0.5 + j, 0.8};
      r.n = {0, 0, 1};
      for (double& v : r.rho) v = 1.0;
      s.sets[1].push_back(r);
    }
  }
  return s;
}

// Geometric factor visibility cos / d^2 (no occluders here).
double Geometry(const Vec3& light, const Receiver& r) {
  const Vec3 d = testing::Sub(r.p, light);
  const double dist = testing::Norm(d);
  return std::max(0.0, -testing::Dot(d, r.n) / dist) / (dist * dist);
}

// Per-candela-of-Y_t basis value (float64): set 0 cd/m^2, set 1 lux.
double BasisValue(const LightDef& l, int set, const Receiver& r, int t, int c, bool with_direct,
                  std::vector<double>* y) {
  const double lambert = set == 0 ? r.rho[c] / testing::kPi : 1.0;
  double v = 0;
  if (with_direct) {
    baker::EvalShBasis(l.degree, testing::Normalised(testing::Sub(r.p, l.position)), y->data());
    v += (*y)[t] * Geometry(l.position, r);
  }
  for (const Vec3& b : kBounce) {
    const Vec3 d = testing::Sub(b, l.position);
    const double dist = testing::Norm(d);
    baker::EvalShBasis(l.degree, testing::Normalised(d), y->data());
    const double arrive = (*y)[t] * (-d[2] / dist) / (dist * dist);  // E at the bounce point
    const double transfer = 0.5 / testing::kPi * 0.3 / (1.0 + std::pow(testing::Norm(testing::Sub(r.p, b)), 2));
    v += arrive * transfer;
  }
  return v * lambert;
}

Bake MakeBake(const TestScene& s) {
  Bake bake;
  bake.scene_name = "engine_test";
  for (const Receiver& r : s.sets[0]) {
    for (int i = 0; i < 3; ++i) {
      bake.mesh.positions.push_back(static_cast<int32_t>(std::lround(r.p[i] * 65536)));
      bake.mesh.normals.push_back(static_cast<int16_t>(std::lround(r.n[i] * 16384)));
    }
  }
  bake.mesh.albedo = s.albedo;
  BakeGrid grid;
  grid.name = "work plane";
  grid.columns = 3;
  grid.rows = 3;
  for (const Receiver& r : s.sets[1]) {
    for (int i = 0; i < 3; ++i) {
      grid.points.push_back(static_cast<int32_t>(std::lround(r.p[i] * 65536)));
      grid.normals.push_back(static_cast<int16_t>(std::lround(r.n[i] * 16384)));
    }
  }
  bake.grids.push_back(grid);
  for (const LightDef& l : kLights) {
    BakeLuminaire lum;
    lum.name = l.name;
    for (int i = 0; i < 3; ++i) lum.position[i] = static_cast<int32_t>(std::lround(l.position[i] * 65536));
    lum.mounting = Mounting::kHanging;
    lum.direct_mode = l.mode;
    lum.sh_degree = static_cast<uint8_t>(l.degree);
    lum.use_sigma = 1;
    lum.default_pan = l.mode == DirectMode::kExactDirect ? 30 << 16 : -45 * 65536;
    lum.default_tilt = l.mode == DirectMode::kExactDirect ? 20 << 16 : 10 << 16;
    lum.lid.candela = testing::ToQ16(testing::CosPowerSamples(l.peak_cd, l.exponent, l.M));
    const bool exact = l.mode == DirectMode::kExactDirect;
    const int terms = ShTermCount(l.degree);
    std::vector<double> y(terms);
    for (int set = 0; set < 2; ++set) {
      const std::vector<Receiver>& rs = s.sets[set];
      const size_t count = rs.size();
      BakeLightReceivers rx;
      std::vector<double> values(terms * count * 3);
      for (int t = 0; t < terms; ++t) {
        for (size_t r = 0; r < count; ++r) {
          for (int c = 0; c < 3; ++c) {
            values[(t * count + r) * 3 + c] = BasisValue(l, set, rs[r], t, c, !exact, &y);
          }
        }
      }
      rx.basis.resize(values.size());
      rx.basis_scale.resize(terms * 3);
      for (int t = 0; t < terms; ++t) {
        for (int c = 0; c < 3; ++c) {
          rx.basis_scale[t * 3 + c] = testing::QuantiseInt16(&values[t * count * 3 + c], count, 3,
                                                             &rx.basis[t * count * 3 + c], 3);
        }
      }
      if (exact) {
        std::vector<double> g;
        for (const Receiver& r : rs) {
          const Vec3 d = testing::Normalised(testing::Sub(r.p, l.position));
          for (int i = 0; i < 3; ++i) rx.direction.push_back(static_cast<int16_t>(std::lround(d[i] * 16384)));
          g.push_back(Geometry(l.position, r));
        }
        rx.geometry_scale = testing::QuantiseUint32(g, &rx.geometry);
      }
      lum.receivers.push_back(rx);
    }
    bake.luminaires.push_back(lum);
  }
  return bake;
}

struct State {
  double pan, tilt, dimmer;
  double rgb[3];
};

struct Outputs {
  std::vector<double> vertex, grid, grid_direct;
};

// float64 on the bake's LID samples, unquantised basis and geometry.
Outputs Reference(const TestScene& s, const State (&st)[2]) {
  Outputs o;
  o.vertex.assign(s.sets[0].size() * 3, 0);
  o.grid.assign(s.sets[1].size() * 3, 0);
  o.grid_direct.assign(s.sets[1].size() * 3, 0);
  for (int li = 0; li < 2; ++li) {
    const LightDef& l = kLights[li];
    const bool exact = l.mode == DirectMode::kExactDirect;
    const std::vector<double> samples =
        testing::FromQ16(testing::ToQ16(testing::CosPowerSamples(l.peak_cd, l.exponent, l.M)));
    const Vec3 axis = baker::BeamAxis(MountingKind::kHanging, st[li].pan, st[li].tilt);
    const std::vector<double> tw =
        baker::TermWeights(baker::LegendreWeights(samples, l.degree), axis, true);
    std::vector<double> y(tw.size());
    for (int set = 0; set < 2; ++set) {
      for (size_t r = 0; r < s.sets[set].size(); ++r) {
        const Receiver& rc = s.sets[set][r];
        for (int c = 0; c < 3; ++c) {
          double indirect = 0;
          for (size_t t = 0; t < tw.size(); ++t) {
            indirect += tw[t] * BasisValue(l, set, rc, static_cast<int>(t), c, !exact, &y);
          }
          double direct = 0;
          if (exact) {
            const double gamma = testing::AngleDeg(testing::Sub(rc.p, l.position), axis);
            direct = testing::LinearLid(samples, gamma) * Geometry(l.position, rc) *
                     (set == 0 ? rc.rho[c] / testing::kPi : 1.0);
          }
          const double gain = st[li].dimmer * st[li].rgb[c];
          if (set == 0) {
            o.vertex[r * 3 + c] += gain * (direct + indirect);
          } else {
            o.grid[r * 3 + c] += gain * (direct + indirect);
            o.grid_direct[r * 3 + c] += gain * direct;
          }
        }
      }
    }
  }
  return o;
}

// Max |fixed - float| relative to the float peak.
double RelativeError(const int32_t* fixed, const std::vector<double>& ref, double* peak_out) {
  double peak = 0, err = 0;
  for (size_t i = 0; i < ref.size(); ++i) {
    peak = std::max(peak, std::fabs(ref[i]));
    err = std::max(err, std::fabs(fixed[i] / kQ12 - ref[i]));
  }
  *peak_out = peak;
  return err / peak;
}

Q16_16 Deg(double d) { return Q16_16::FromRatio(std::llround(d * 1000), 1000); }
Q1_15 Level(double v) { return Q1_15::FromRaw(static_cast<int16_t>(std::lround(v * 32767))); }

class EngineTest : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = MakeScene();
    ASSERT_TRUE(engine_.Open(MakeBake(scene_)).ok());
  }
  // The float state matching what the engine holds.
  void CheckAgainstFloat(const char* label) {
    State st[2];
    for (int i = 0; i < 2; ++i) {
      const FixtureState f = engine_.state(i);
      st[i] = {f.pan_deg.raw() / 65536.0, f.tilt_deg.raw() / 65536.0, f.dimmer.raw() / 32767.0,
               {f.rgb[0].raw() / 32767.0, f.rgb[1].raw() / 32767.0, f.rgb[2].raw() / 32767.0}};
    }
    const Outputs ref = Reference(scene_, st);
    double pv, pg, pd;
    const double ev = RelativeError(engine_.vertex_luminance().raw(), ref.vertex, &pv);
    const double eg = RelativeError(engine_.grid_illuminance(0).raw(), ref.grid, &pg);
    const double ed = RelativeError(engine_.grid_direct_illuminance(0).raw(), ref.grid_direct, &pd);
    std::printf("  %s: vertices peak %.3f cd/m2 err %.2e of peak; grid peak %.2f lux err %.2e; "
                "grid direct peak %.2f lux err %.2e\n",
                label, pv, ev, pg, eg, pd, ed);
    EXPECT_GT(pv, 1.0);
    EXPECT_LE(ev, 1e-3) << label;  // acceptance bar: 0.1% of peak
    EXPECT_LE(eg, 1e-3) << label;
    EXPECT_LE(ed, 1e-3) << label;
  }
  std::vector<int32_t> Vertices() const {
    const LuminanceView view = engine_.vertex_luminance();
    return std::vector<int32_t>(view.begin(), view.end());
  }
  TestScene scene_;
  Engine engine_;
};

TEST_F(EngineTest, OpenMatchesFloat64) {
  ASSERT_TRUE(engine_.is_open());
  EXPECT_EQ(engine_.luminaire_count(), 2);
  EXPECT_EQ(engine_.vertex_count(), 16u);
  EXPECT_EQ(engine_.FindLuminaire("wash"), 1);
  EXPECT_EQ(engine_.FindLuminaire("nope"), -1);
  EXPECT_EQ(engine_.last_update_luminaires_recombined(), 2);
  EXPECT_EQ(engine_.state(0).pan_deg, Q16_16::FromInt(30));
  CheckAgainstFloat("defaults");
  engine_.Update();  // nothing changed: nothing done, same output
  EXPECT_EQ(engine_.last_update_luminaires_recombined(), 0);
  EXPECT_EQ(engine_.last_update_terms_recombined(), 0);
  CheckAgainstFloat("defaults again");
}

TEST_F(EngineTest, DimmerChangeDoesNotRecombineAndScalesLinearly) {
  const std::vector<int32_t> full = Vertices();
  ASSERT_TRUE(engine_.SetDimmer(0, Level(0)).ok());
  engine_.Update();
  EXPECT_EQ(engine_.last_update_luminaires_recombined(), 0);
  EXPECT_EQ(engine_.last_update_terms_recombined(), 0);
  const std::vector<int32_t> off = Vertices();
  ASSERT_TRUE(engine_.SetDimmer(0, Q1_15::FromRaw(16384)).ok());
  engine_.Update();
  EXPECT_EQ(engine_.last_update_luminaires_recombined(), 0);
  const std::vector<int32_t> half = Vertices();
  const double f = 16384.0 / 32767.0;
  for (size_t i = 0; i < full.size(); ++i) {
    EXPECT_NEAR(half[i], off[i] + f * (full[i] - off[i]), 2.0) << i;  // 2 LSB of rounding
  }
  CheckAgainstFloat("spot at half");
}

TEST_F(EngineTest, PanChangeRecombinesOnlyThatLuminaire) {
  ASSERT_TRUE(engine_.SetPanTilt(1, Deg(60), Deg(35)).ok());
  engine_.Update();
  EXPECT_EQ(engine_.last_update_luminaires_recombined(), 1);
  // One pass per non-zero term per receiver set: at most (6+1)^2 x 2.
  EXPECT_GT(engine_.last_update_terms_recombined(), 0);
  EXPECT_LE(engine_.last_update_terms_recombined(), ShTermCount(6) * 2);
  CheckAgainstFloat("wash at pan 60 tilt 35");
  ASSERT_TRUE(engine_.SetPanTilt(0, Deg(-150.5), Deg(42.25)).ok());
  engine_.Update();
  EXPECT_EQ(engine_.last_update_luminaires_recombined(), 1);
  EXPECT_LE(engine_.last_update_terms_recombined(), ShTermCount(8) * 2);
  CheckAgainstFloat("spot at pan -150.5 tilt 42.25");
  // Straight down: the m != 0 terms vanish and are skipped.
  ASSERT_TRUE(engine_.SetPanTilt(0, Deg(0), Deg(0)).ok());
  engine_.Update();
  std::printf("  spot straight down: %d term passes (of %d)\n",
              engine_.last_update_terms_recombined(), ShTermCount(8) * 2);
  EXPECT_LT(engine_.last_update_terms_recombined(), ShTermCount(8) * 2);
  CheckAgainstFloat("spot straight down");
}

TEST_F(EngineTest, ColourScalesChannels) {
  ASSERT_TRUE(engine_.SetDimmer(0, Level(0)).ok());
  engine_.Update();
  const std::vector<int32_t> wash_only = Vertices();
  ASSERT_TRUE(engine_.SetDimmer(0, Level(1)).ok());
  engine_.Update();
  const std::vector<int32_t> white = Vertices();
  ASSERT_TRUE(engine_.SetColour(0, Level(1), Level(0.5), Level(0)).ok());
  engine_.Update();
  EXPECT_EQ(engine_.last_update_luminaires_recombined(), 0);
  const std::vector<int32_t> tinted = Vertices();
  const double gain[3] = {1.0, 16384.0 / 32767.0, 0.0};
  for (size_t i = 0; i < white.size(); ++i) {
    const double spot = white[i] - wash_only[i];
    EXPECT_NEAR(tinted[i], wash_only[i] + gain[i % 3] * spot, 2.0) << i;
  }
  CheckAgainstFloat("spot tinted");
}

TEST_F(EngineTest, BadIndexClampingAndWrapping) {
  for (int bad : {-1, 2, 1000}) {
    EXPECT_EQ(engine_.SetDimmer(bad, Level(1)).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(engine_.SetPanTilt(bad, Deg(0), Deg(0)).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ(engine_.SetColour(bad, Level(1), Level(1), Level(1)).code(),
              StatusCode::kInvalidArgument);
    EXPECT_EQ(engine_.state(bad).dimmer.raw(), 0);
  }
  ASSERT_TRUE(engine_.SetDimmer(1, Q1_15::FromRaw(-300)).ok());
  EXPECT_EQ(engine_.state(1).dimmer.raw(), 0);
  ASSERT_TRUE(engine_.SetColour(1, Q1_15::FromRaw(-1), Q1_15::FromRaw(32767), Level(0.25)).ok());
  EXPECT_EQ(engine_.state(1).rgb[0].raw(), 0);
  EXPECT_EQ(engine_.state(1).rgb[1].raw(), 32767);
  ASSERT_TRUE(engine_.SetPanTilt(0, Deg(-180), Deg(540)).ok());
  EXPECT_EQ(engine_.state(0).pan_deg, Q16_16::FromInt(180));
  EXPECT_EQ(engine_.state(0).tilt_deg, Q16_16::FromInt(180));
  ASSERT_TRUE(engine_.SetPanTilt(0, Deg(370), Deg(-340)).ok());
  EXPECT_EQ(engine_.state(0).pan_deg, Q16_16::FromInt(10));
  EXPECT_EQ(engine_.state(0).tilt_deg, Q16_16::FromInt(20));
  ASSERT_TRUE(engine_.SetDimmer(1, Level(1)).ok());
  ASSERT_TRUE(engine_.SetColour(1, Level(1), Level(1), Level(1)).ok());
  engine_.Update();
  // The same as asking for the wrapped angles directly.
  Engine direct;
  ASSERT_TRUE(direct.Open(MakeBake(scene_)).ok());
  ASSERT_TRUE(direct.SetPanTilt(0, Deg(10), Deg(20)).ok());
  direct.Update();
  const LuminanceView direct_view = direct.vertex_luminance();
  EXPECT_EQ(Vertices(), std::vector<int32_t>(direct_view.begin(), direct_view.end()));
  CheckAgainstFloat("wrapped angles");
  Engine closed;
  EXPECT_EQ(closed.SetDimmer(0, Level(1)).code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(closed.vertex_luminance().empty());
  EXPECT_EQ(closed.vertex_luminance().raw(), nullptr);
  EXPECT_TRUE(engine_.grid_illuminance(1).empty());
  EXPECT_TRUE(engine_.grid_direct_illuminance(-1).empty());
}

// The typed outputs: sized by what they cover, channel reads equal to the
// raw buffer, luminance and illuminance not interchangeable.
static_assert(!std::is_convertible<LuminanceView, IlluminanceView>::value, "quantities do not mix");
static_assert(!std::is_convertible<IlluminanceView, LuminanceView>::value, "quantities do not mix");
TEST_F(EngineTest, OutputViewsCoverTheirReceivers) {
  const LuminanceView vertices = engine_.vertex_luminance();
  ASSERT_EQ(vertices.receivers(), engine_.vertex_count());
  ASSERT_EQ(vertices.raw_size(), size_t{engine_.vertex_count()} * 3);
  bool any_lit = false;
  for (uint32_t v = 0; v < vertices.receivers(); ++v) {
    for (uint32_t c = 0; c < 3; ++c) {
      ASSERT_EQ(vertices.at(v, c).raw(), vertices.raw()[v * 3 + c]);
      any_lit = any_lit || vertices.at(v, c).raw() > 0;
    }
  }
  EXPECT_TRUE(any_lit);
  const IlluminanceView total = engine_.grid_illuminance(0);
  const IlluminanceView direct = engine_.grid_direct_illuminance(0);
  EXPECT_EQ(total.receivers(), engine_.bake().grids[0].point_count());
  EXPECT_EQ(direct.receivers(), total.receivers());
  EXPECT_FALSE(total.empty());
}

// Every vertex luminance and the first grid's 27 illuminances (total and
// direct) of two engines, bit for bit.
void ExpectSameResults(const Engine& a, const Engine& b) {
  const uint32_t n = a.vertex_count() * 3;
  for (uint32_t i = 0; i < n; ++i) ASSERT_EQ(a.vertex_luminance().raw()[i], b.vertex_luminance().raw()[i]);
  for (uint32_t i = 0; i < 27; ++i) {
    ASSERT_EQ(a.grid_illuminance(0).raw()[i], b.grid_illuminance(0).raw()[i]);
    ASSERT_EQ(a.grid_direct_illuminance(0).raw()[i], b.grid_direct_illuminance(0).raw()[i]);
  }
}

TEST_F(EngineTest, ResultDoesNotDependOnTheOrderOfSetCalls) {
  Engine other;
  ASSERT_TRUE(other.Open(MakeBake(scene_)).ok());
  ASSERT_TRUE(engine_.SetPanTilt(0, Deg(12.5), Deg(33)).ok());
  ASSERT_TRUE(engine_.SetDimmer(1, Level(0.3)).ok());
  ASSERT_TRUE(engine_.SetColour(0, Level(0.9), Level(0.2), Level(0.6)).ok());
  ASSERT_TRUE(engine_.SetPanTilt(1, Deg(-20), Deg(5)).ok());
  engine_.Update();
  // Reverse order, with an intermediate Update and a detour through another aim.
  ASSERT_TRUE(other.SetPanTilt(1, Deg(-20), Deg(5)).ok());
  ASSERT_TRUE(other.SetColour(0, Level(0.9), Level(0.2), Level(0.6)).ok());
  other.Update();
  ASSERT_TRUE(other.SetPanTilt(0, Deg(80), Deg(60)).ok());
  ASSERT_TRUE(other.SetDimmer(1, Level(0.3)).ok());
  other.Update();
  ASSERT_TRUE(other.SetPanTilt(0, Deg(12.5), Deg(33)).ok());
  other.Update();
  ASSERT_NO_FATAL_FAILURE(ExpectSameResults(engine_, other));
  CheckAgainstFloat("mixed state");
}

TEST_F(EngineTest, FreeingTheCopiedDirectInputsChangesNoResult) {
  EngineOptions lean;
  lean.keep_direct_inputs = false;
  Engine other;
  ASSERT_TRUE(other.Open(MakeBake(scene_), lean).ok());
  size_t kept = 0, freed = 0;
  for (size_t i = 0; i < other.bake().luminaires.size(); ++i) {
    const BakeLuminaire& b = other.bake().luminaires[i];
    if (b.direct_mode != DirectMode::kExactDirect) continue;
    for (size_t s = 0; s < b.receivers.size(); ++s) {
      kept += engine_.bake().luminaires[i].receivers[s].geometry.size();
      freed += b.receivers[s].direction.size() + b.receivers[s].geometry.size();
    }
  }
  EXPECT_GT(kept, 0u);  // the default keeps them; the scene has an exact-direct luminaire
  EXPECT_EQ(freed, 0u);
  for (Engine* e : {&engine_, &other}) {
    ASSERT_TRUE(e->SetPanTilt(0, Deg(-35), Deg(20)).ok());
    ASSERT_TRUE(e->SetPanTilt(1, Deg(15), Deg(40)).ok());
    ASSERT_TRUE(e->SetDimmer(0, Level(0.7)).ok());
    e->Update();
  }
  ASSERT_NO_FATAL_FAILURE(ExpectSameResults(engine_, other));
}

TEST_F(EngineTest, DroppingTheGridsChangesNoVertex) {
  EngineOptions no_grids;
  no_grids.grids = false;
  Engine other;
  ASSERT_TRUE(other.Open(MakeBake(scene_), no_grids).ok());
  ASSERT_FALSE(engine_.grid_illuminance(0).empty());  // the scene has a grid ...
  EXPECT_TRUE(other.grid_illuminance(0).empty());      // ... that this engine dropped
  EXPECT_TRUE(other.grid_direct_illuminance(0).empty());
  EXPECT_TRUE(other.bake().grids.empty());
  for (const BakeLuminaire& b : other.bake().luminaires) EXPECT_EQ(b.receivers.size(), 1u);
  const Status valid = ValidateBake(other.bake());  // what is left is still a whole bake
  EXPECT_TRUE(valid.ok()) << valid.ToString();
  for (Engine* e : {&engine_, &other}) {
    ASSERT_TRUE(e->SetPanTilt(0, Deg(-35), Deg(20)).ok());
    ASSERT_TRUE(e->SetPanTilt(1, Deg(15), Deg(40)).ok());
    ASSERT_TRUE(e->SetColour(1, Level(0.9), Level(0.4), Level(0.1)).ok());
    e->Update();
  }
  const uint32_t n = engine_.vertex_count() * 3;
  ASSERT_EQ(other.vertex_count() * 3, n);
  for (uint32_t i = 0; i < n; ++i) {
    ASSERT_EQ(engine_.vertex_luminance().raw()[i], other.vertex_luminance().raw()[i]) << i;
  }
}

TEST_F(EngineTest, ADarkLuminaireIsRebuiltWhenLit) {
  ASSERT_TRUE(engine_.SetDimmer(0, Level(0)).ok());
  ASSERT_TRUE(engine_.SetPanTilt(0, Deg(-70), Deg(25)).ok());
  engine_.Update();
  EXPECT_EQ(engine_.last_update_luminaires_recombined(), 0);  // moving in black costs nothing
  ASSERT_TRUE(engine_.SetDimmer(0, Level(0.8)).ok());
  engine_.Update();
  EXPECT_EQ(engine_.last_update_luminaires_recombined(), 1);
  CheckAgainstFloat("spot moved in black, then lit");
}

TEST_F(EngineTest, SettersAndUpdateDoNotAllocate) {
  g_allocations = 0;
  g_count_allocations = true;  // the counter works
  void* volatile probe = ::operator new(64);
  ::operator delete(probe);
  g_count_allocations = false;
  ASSERT_EQ(g_allocations.load(), 1);
  g_allocations = 0;
  g_count_allocations = true;
  Status a = engine_.SetPanTilt(0, Deg(-33), Deg(47));
  Status b = engine_.SetDimmer(1, Level(0.7));
  Status c = engine_.SetColour(0, Level(0.2), Level(1), Level(0.5));
  Status bad = engine_.SetDimmer(7, Level(1));
  engine_.Update();
  const int recombined = engine_.last_update_luminaires_recombined();
  g_count_allocations = false;
  EXPECT_TRUE(a.ok() && b.ok() && c.ok());
  EXPECT_EQ(bad.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(recombined, 1);
  EXPECT_EQ(g_allocations.load(), 0);
}

TEST_F(EngineTest, GridDirectIsTheExactDirectLuminaireOnly) {
  ASSERT_TRUE(engine_.SetDimmer(0, Level(0)).ok());
  engine_.Update();
  for (uint32_t i = 0; i < 27; ++i) EXPECT_EQ(engine_.grid_direct_illuminance(0).raw()[i], 0);
  for (uint32_t i = 0; i < 27; ++i) EXPECT_GT(engine_.grid_illuminance(0).raw()[i], 0);
}

TEST_F(EngineTest, OpenRejectsAnInconsistentBakeAndKeepsThePrevious) {
  const std::vector<int32_t> before = Vertices();
  Bake bad = MakeBake(scene_);
  bad.luminaires[1].receivers[1].basis.pop_back();
  Status st = engine_.Open(bad);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  std::printf("  rejected: %s\n", st.ToString().c_str());
  Bake bad2 = MakeBake(scene_);
  bad2.luminaires[0].receivers[0].geometry.clear();
  EXPECT_EQ(engine_.Open(bad2).code(), StatusCode::kInvalidArgument);
  Bake bad3 = MakeBake(scene_);
  bad3.luminaires[0].sh_degree = 17;
  EXPECT_EQ(engine_.Open(bad3).code(), StatusCode::kInvalidArgument);
  Bake bad4 = MakeBake(scene_);
  bad4.luminaires[0].lid.candela[3] = -1;
  EXPECT_EQ(engine_.Open(bad4).code(), StatusCode::kInvalidArgument);
  ASSERT_TRUE(engine_.is_open());
  EXPECT_EQ(Vertices(), before);
  Engine fresh;
  EXPECT_FALSE(fresh.Open(bad).ok());
  EXPECT_FALSE(fresh.is_open());
}

TEST_F(EngineTest, OpenFromAFileMatchesOpenFromMemory) {
  const std::string path = ::testing::TempDir() + "engine_test_" + std::to_string(getpid()) + ".rlb";
  ASSERT_TRUE(WriteBake(MakeBake(scene_), path).ok());
  Engine from_file;
  const Status st = from_file.Open(path);
  ASSERT_TRUE(st.ok()) << st.ToString();
  std::remove(path.c_str());
  const uint32_t n = engine_.vertex_count() * 3;
  for (uint32_t i = 0; i < n; ++i) ASSERT_EQ(from_file.vertex_luminance().raw()[i], engine_.vertex_luminance().raw()[i]);
  EXPECT_EQ(from_file.Open(path + ".missing").code(), StatusCode::kNotFound);
  EXPECT_TRUE(from_file.is_open());  // keeps the bake it had
}

}  // namespace
}  // namespace relight
