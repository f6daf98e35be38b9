// The runtime's fixed-point pieces for real luminaires against their float64
// mirrors in the baker: fixture frames (mounting, yaw, pan, tilt, roll),
// aiming at a point, Ivanic-Ruedenberg SH rotation, (C, gamma) table lookup
// and the exact direct term of a table LID.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "bake_lid.h"
#include "direct.h"
#include "engine_test_support.h"
#include "fixture_frame.h"
#include "lid_table.h"
#include "relight/baker/fixture_frame.h"
#include "relight/baker/photometric_file.h"
#include "relight/baker/analytic_photometry.h"
#include "relight/baker/sh_rotation.h"
#include "relight/baker/photometry.h"
#include "relight/engine/engine.h"
#include "relight/engine/sh_rotation.h"
#include "weights.h"

namespace relight {
namespace {

using baker::MountingKind;
using baker::Vec3;

constexpr double kQ30 = 1073741824.0;

Q16_16 Deg(double d) { return Q16_16::FromRaw(static_cast<int32_t>(std::llround(d * 65536.0))); }
double FromDeg(Q16_16 d) { return d.raw() / 65536.0; }

Mounting ToMounting(MountingKind m) {
  return m == MountingKind::kHanging ? Mounting::kHanging
                                     : m == MountingKind::kStanding ? Mounting::kStanding
                                                                    : Mounting::kWall;
}

FixtureFrameQ30 FrameQ30(const baker::FixturePose& p) {
  FixturePoseQ16 q;
  q.mounting = ToMounting(p.mounting);
  q.yaw_deg = Deg(p.yaw_deg);
  q.pan_deg = Deg(p.pan_deg);
  q.tilt_deg = Deg(p.tilt_deg);
  q.roll_deg = Deg(p.roll_deg);
  FixtureFrameQ30 f;
  MakeFixtureFrameQ30(q, &f);
  return f;
}

double MaxDiff(const int32_t q[3], const Vec3& v) {
  double worst = 0;
  for (int i = 0; i < 3; ++i) worst = std::max(worst, std::abs(q[i] / kQ30 - v[i]));
  return worst;
}

baker::FixturePose RandomPose(std::mt19937* rng, int i) {
  std::uniform_real_distribution<double> a(-360, 360);
  return baker::FixturePose{static_cast<MountingKind>(i % 3), a(*rng), a(*rng), a(*rng), a(*rng)};
}

TEST(FixtureFrameQ30, MatchesFloat64ForEveryMountingAndAngle) {
  std::mt19937 rng(1);
  double worst = 0;
  for (int i = 0; i < 3000; ++i) {
    const baker::FixturePose p = RandomPose(&rng, i);
    // The float64 frame at the angles the fixed-point input can hold.
    const baker::FixturePose exact{p.mounting, FromDeg(Deg(p.yaw_deg)), FromDeg(Deg(p.pan_deg)),
                                   FromDeg(Deg(p.tilt_deg)), FromDeg(Deg(p.roll_deg))};
    const baker::FixtureFrame f = baker::MakeFixtureFrame(exact);
    const FixtureFrameQ30 q = FrameQ30(p);
    worst = std::max({worst, MaxDiff(q.c0, f.c0), MaxDiff(q.c90, f.c90), MaxDiff(q.axis, f.axis)});
  }
  std::printf("fixture frame: max |Q1.30 - float64| = %.2e (%.1f LSB)\n", worst, worst * kQ30);
  EXPECT_LT(worst * kQ30, 8.0);
}

TEST(FixtureFrameQ30, AxisIsBeamAxisQ30ForHangingAndStanding) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> a(-360, 360);
  for (int i = 0; i < 2000; ++i) {
    const Mounting m = i % 2 ? Mounting::kStanding : Mounting::kHanging;
    FixturePoseQ16 p;
    p.mounting = m;
    p.pan_deg = Deg(a(rng));
    p.tilt_deg = Deg(a(rng));
    p.roll_deg = Deg(a(rng));
    FixtureFrameQ30 f;
    MakeFixtureFrameQ30(p, &f);
    int32_t axis[3];
    BeamAxisQ30(m, p.pan_deg, p.tilt_deg, axis);
    ASSERT_EQ(f.axis[0], axis[0]);
    ASSERT_EQ(f.axis[1], axis[1]);
    ASSERT_EQ(f.axis[2], axis[2]);
  }
}

TEST(FixtureFrameQ30, AimAtPutsTheAxisOnTheTarget) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(-6, 6), yaw(-180, 180);
  double worst_deg = 0;
  for (int i = 0; i < 2000; ++i) {
    const MountingKind mk = static_cast<MountingKind>(i % 3);
    const Vec3 pos{x(rng), x(rng), x(rng)}, target{x(rng), x(rng), x(rng)};
    const double yaw_deg = i % 2 ? yaw(rng) : 0.0;
    int32_t p16[3], t16[3];
    for (int k = 0; k < 3; ++k) {
      p16[k] = static_cast<int32_t>(std::llround(pos[k] * 65536));
      t16[k] = static_cast<int32_t>(std::llround(target[k] * 65536));
    }
    Q16_16 pan, tilt;
    ASSERT_TRUE(AimAtQ16(ToMounting(mk), Deg(yaw_deg), p16, t16, &pan, &tilt));
    const baker::FixtureFrame f =
        baker::MakeFixtureFrame({mk, FromDeg(Deg(yaw_deg)), FromDeg(pan), FromDeg(tilt), 0});
    Vec3 d{};
    double len = 0;
    for (int k = 0; k < 3; ++k) {
      d[k] = (t16[k] - p16[k]) / 65536.0;
      len += d[k] * d[k];
    }
    len = std::sqrt(len);
    const double cosang = (d[0] * f.axis[0] + d[1] * f.axis[1] + d[2] * f.axis[2]) / len;
    worst_deg = std::max(worst_deg, std::acos(std::min(1.0, cosang)) * 180 / 3.14159265358979);
    double fp = 0, ft = 0;
    baker::AimAtPose(mk, FromDeg(Deg(yaw_deg)), pos, target, &fp, &ft);
    ASSERT_NEAR(FromDeg(tilt), ft, 0.01);
  }
  std::printf("aim at a point: worst miss %.5f degrees\n", worst_deg);
  EXPECT_LT(worst_deg, 0.001);
  const int32_t same[3] = {0, 0, 0};
  Q16_16 pan = Deg(7), tilt = Deg(8);
  EXPECT_FALSE(AimAtQ16(Mounting::kHanging, Deg(0), same, same, &pan, &tilt));
  EXPECT_EQ(pan, Deg(7));
}

void RotationRows(const FixtureFrameQ30& f, int32_t r[3][3]) {
  for (int i = 0; i < 3; ++i) {
    r[i][0] = f.c0[i];
    r[i][1] = f.c90[i];
    r[i][2] = -f.axis[i];
  }
}

TEST(ShRotationQ30, MatchesFloat64Recurrence) {
  auto tables = std::make_unique<ShRotationTables>();
  InitShRotationTables(tables.get());
  std::mt19937 rng(4);
  std::vector<int32_t> d(kShRotationValues);
  double worst = 0;
  for (int i = 0; i < 30; ++i) {
    const FixtureFrameQ30 f = FrameQ30(RandomPose(&rng, i));
    int32_t r[3][3];
    RotationRows(f, r);
    double rf[3][3];
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) rf[a][b] = r[a][b] / kQ30;
    }
    ShRotationMatricesQ30(*tables, kMaxShDegree, r, d.data());
    const std::vector<double> ref = baker::ShRotationMatrices(kMaxShDegree, rf);
    for (size_t k = 0; k < ref.size(); ++k) worst = std::max(worst, std::abs(d[k] / kQ30 - ref[k]));
  }
  std::printf("SH rotation up to l = %d: max |Q1.30 - float64| = %.2e (%.1f LSB)\n", kMaxShDegree,
              worst, worst * kQ30);
  // The recurrence's rounding grows with the degree: measured 2.8e-8 (30 LSB)
  // at l = 20 and 4.8e-8 (51 LSB) at l = 22; the bound had been 2e-8 at l = 16.
  EXPECT_LT(worst, 6e-8);
}

TEST(ShRotationQ30, RotatedCoefficientsMatchFloat64) {
  auto tables = std::make_unique<ShRotationTables>();
  InitShRotationTables(tables.get());
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> c(-2000, 2000);
  std::vector<int32_t> d(kShRotationValues);
  for (int degree : {0, 1, 3, 8, 16}) {
    const int terms = ShTermCount(degree);
    std::vector<double> coef(terms);
    std::vector<int64_t> coef_q16(terms), out_q16(terms);
    for (int t = 0; t < terms; ++t) {
      coef[t] = c(rng);
      coef_q16[t] = std::llround(coef[t] * 65536);
      coef[t] = static_cast<double>(coef_q16[t]) / 65536.0;
    }
    const FixtureFrameQ30 f = FrameQ30(RandomPose(&rng, degree));
    int32_t r[3][3];
    double rf[3][3];
    RotationRows(f, r);
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) rf[a][b] = r[a][b] / kQ30;
    }
    ShRotationMatricesQ30(*tables, degree, r, d.data());
    RotateShQ16(degree, d.data(), coef_q16.data(), out_q16.data());
    const std::vector<double> ref =
        baker::RotateSh(degree, baker::ShRotationMatrices(degree, rf), coef);
    for (int t = 0; t < terms; ++t) {
      ASSERT_NEAR(static_cast<double>(out_q16[t]) / 65536.0, ref[t], 2000 * 2e-8 * (2 * degree + 1) + 1e-4) << t;
    }
  }
}

// The bake's full-circle table of a real-ish LID, and its view.
struct TableFixture {
  std::vector<int32_t> c, g;
  std::vector<int64_t> v;
  baker::FullCircleTable full;
  LidTableView view() const {
    LidTableView t;
    t.c_deg_q16 = c.data();
    t.planes = static_cast<uint32_t>(c.size());
    t.gamma_deg_q16 = g.data();
    t.gammas = static_cast<uint32_t>(g.size());
    t.candela_q16 = v.data();
    return t;
  }
};

TableFixture MakeTable(const baker::PhotometricTable& table) {
  TableFixture f;
  f.full = baker::ExpandToFullCircle(table);
  for (double c : f.full.c_deg) f.c.push_back(static_cast<int32_t>(std::llround(c * 65536)));
  for (double g : f.full.gamma_deg) f.g.push_back(static_cast<int32_t>(std::llround(g * 65536)));
  for (double v : f.full.candela) f.v.push_back(std::llround(v * 65536));
  return f;
}

TEST(LidTable, BilinearLookupMatchesFloat64) {
  for (const baker::PhotometricFixture& fx : baker::PhotometricFixtures()) {
    if (fx.table.symmetry == baker::CSymmetry::kAxial) continue;
    SCOPED_TRACE(fx.file_name);
    const TableFixture t = MakeTable(fx.table);
    std::mt19937 rng(6);
    std::uniform_int_distribution<uint32_t> c_bam(0, 0xFFFFFFFFu), g_bam(0, 0x80000000u);
    double worst = 0;
    for (int i = 0; i < 4000; ++i) {
      const Bam c = c_bam(rng), g = g_bam(rng);
      const double got = static_cast<double>(LidTableIntensityQ16(t.view(), c, g)) / 65536.0;
      const double want = t.full.Evaluate(c / 4294967296.0 * 360, g / 4294967296.0 * 360);
      worst = std::max(worst, std::abs(got - want));
    }
    EXPECT_LT(worst, 1e-4 * fx.table.PeakCandela());
    // Knots exactly, and 0 outside the gamma range.
    EXPECT_EQ(LidTableIntensityQ16(t.view(), 0, 0), t.v[0]);
    if (fx.table.gamma_deg.back() < 180) {
      EXPECT_EQ(LidTableIntensityQ16(t.view(), 0, 0x7FFFFFFFu), 0);
    }
  }
}

TEST(LidTable, DirectIlluminanceMatchesFloat64InTheFixtureFrame) {
  const baker::PhotometricFixture fx = baker::PhotometricFixtures()[4];  // no symmetry
  const TableFixture t = MakeTable(fx.table);
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0, 1);
  double worst = 0;
  for (int i = 0; i < 500; ++i) {
    const baker::FixturePose p = RandomPose(&rng, i);
    const FixtureFrameQ30 fq = FrameQ30(p);
    baker::FixtureFrame f;
    for (int k = 0; k < 3; ++k) {
      f.c0[k] = fq.c0[k] / kQ30;
      f.c90[k] = fq.c90[k] / kQ30;
      f.axis[k] = fq.axis[k] / kQ30;
    }
    Vec3 d{n(rng), n(rng), n(rng)};
    const double len = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    int16_t dq[3];
    for (int k = 0; k < 3; ++k) {
      dq[k] = static_cast<int16_t>(std::lround(d[k] / len * 16384));
      d[k] = dq[k] / 16384.0;
    }
    const QuantScale scale{1 << 29, -20};  // 2^-21 m^-2 per LSB
    const uint32_t geometry = 1u << 20;   // G = 0.5 m^-2
    const double e =
        static_cast<double>(DirectIlluminanceTableQ20(dq, geometry, scale, fq, t.view())) / 1048576.0;
    double c = 0, g = 0;
    const double dl = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    baker::PhotometricAngles(f, Vec3{d[0] / dl, d[1] / dl, d[2] / dl}, &c, &g);
    worst = std::max(worst, std::abs(e - 0.5 * t.full.Evaluate(c, g)));
  }
  // Direction quantisation (Q1.14) moves the angles by ~0.004 degrees.
  EXPECT_LT(worst, 2e-3 * fx.table.PeakCandela());
}

// The engine's per-term weights for a (C, gamma) LID are its fixture-frame SH
// coefficients rotated to the aim. A bake whose basis is the identity (term t
// lights vertex t with 1 cd/m^2 per candela) shows them directly.
TEST(EngineTableLid, TermWeightsAreTheRotatedCoefficients) {
  const int degree = 6, terms = ShTermCount(degree);
  const baker::PhotometricFixture fx = baker::PhotometricFixtures()[4];  // no symmetry
  baker::Lid lid = baker::MakeLid(fx.table);
  baker::Luminaire lum;
  lum.name = "asym";
  lum.mounting = MountingKind::kWall;
  lum.yaw_deg = 30;
  lum.lid = lid;
  Bake bake;
  bake.scene_name = "identity";
  for (int t = 0; t < terms; ++t) {
    bake.mesh.positions.insert(bake.mesh.positions.end(), {t << 16, 0, 0});
    bake.mesh.normals.insert(bake.mesh.normals.end(), {0, 0, 16384});
    bake.mesh.albedo.insert(bake.mesh.albedo.end(), {30000, 30000, 30000});
  }
  BakeLuminaire b;
  b.name = "asym";
  b.direct_mode = DirectMode::kAllInSh;
  b.sh_degree = static_cast<uint8_t>(degree);
  b.use_sigma = 1;
  baker::FillBakeLuminaireLid(lum, degree, 720, &b);
  BakeLightReceivers rx;
  rx.basis.assign(static_cast<size_t>(terms) * terms * 3, 0);
  for (int t = 0; t < terms; ++t) {
    for (int c = 0; c < 3; ++c) {
      rx.basis[(static_cast<size_t>(t) * terms + t) * 3 + c] = 16384;
      rx.basis_scale.push_back(testing::ToQuantScale(1.0 / 16384));
    }
  }
  b.receivers.push_back(rx);
  bake.luminaires.push_back(b);
  Engine engine;
  const Status st = engine.Open(bake);
  ASSERT_TRUE(st.ok()) << st.ToString();
  std::vector<double> local(terms);
  for (int t = 0; t < terms; ++t) {
    local[t] = static_cast<double>(b.lid.sh[t]) / 65536.0 *
               baker::SigmaFactor(degree, ShDegreeOf(t));
  }
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> a(-180, 180);
  double worst = 0, largest = 0;
  for (int i = 0; i < 6; ++i) {
    const double pan = a(rng), tilt = a(rng), roll = a(rng);
    ASSERT_TRUE(engine.SetPanTilt(0, Deg(pan), Deg(tilt)).ok());
    ASSERT_TRUE(engine.SetRoll(0, Deg(roll)).ok());
    engine.Update();
    const baker::FixtureFrame f = baker::MakeFixtureFrame(
        {MountingKind::kWall, FromDeg(Deg(30)), FromDeg(Deg(pan)), FromDeg(Deg(tilt)),
         FromDeg(Deg(roll))});
    double r[3][3];
    for (int k = 0; k < 3; ++k) {
      r[k][0] = f.c0[k];
      r[k][1] = f.c90[k];
      r[k][2] = -f.axis[k];
    }
    const std::vector<double> world =
        baker::RotateSh(degree, baker::ShRotationMatrices(degree, r), local);
    for (int t = 0; t < terms; ++t) {
      const double got = engine.vertex_luminance().raw()[3 * t] / 4096.0;
      worst = std::max(worst, std::abs(got - world[t]));
      largest = std::max(largest, std::abs(world[t]));
    }
  }
  std::printf("engine term weights vs float64 rotation: max error %.2e of the largest (%.1f cd)\n",
              worst / largest, largest);
  EXPECT_LT(worst, 1e-4 * largest);
}

}  // namespace
}  // namespace relight
