// The aimed direct term's AVX2 and AVX-512 bodies (direct_aimed_simd.h)
// against its scalar path: the same bits for every receiver, over directions all round the
// sphere (the acos table's both ends and its small-u start), LIDs from one
// sample to 720 with the steepest steps the format allows, geometry from 0 to
// 2^32 - 1, luminance and lux, write and add (near the int32 top and
// negative), and receiver counts that leave a scalar tail.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "direct_aimed.h"
#include "direct_aimed_simd.h"
#include "gamma_table.h"
#include "recombine_dispatch.h"
#include "relight/bake/bake_limits.h"
#include "relight/base/fixed_math.h"
#include "weights.h"

namespace relight {
namespace {

class LevelCap {  // the paths up to `cap` for this scope
 public:
  explicit LevelCap(SimdLevel cap) { SetSimdLevelCap(cap); }
  ~LevelCap() { SetSimdLevelCap(SimdLevel::kAvx512Vnni); }
  LevelCap(const LevelCap&) = delete;
  LevelCap& operator=(const LevelCap&) = delete;
};

struct Receivers {
  std::vector<int16_t> direction;
  std::vector<uint32_t> geometry, rho;
  DirectPoints points;
};

// n receivers: a third spread over the sphere, a third within a few degrees
// of the axis (the table's root end), a third within a few degrees of its
// reverse; 1 in 11 without geometry.
Receivers MakeReceivers(uint32_t n, const double axis[3], QuantScale scale, std::mt19937_64* rng) {
  Receivers r;
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_int_distribution<uint32_t> g(0, 0xffffffffu);
  for (uint32_t i = 0; i < n; ++i) {
    const double spread = i % 3 == 0 ? 50.0 : (i % 3 == 1 ? 0.03 : 0.05);
    const double sign = i % 3 == 2 ? -1.0 : 1.0;
    double d[3], len = 0;
    for (int c = 0; c < 3; ++c) {
      d[c] = sign * axis[c] + spread * normal(*rng);
      len += d[c] * d[c];
    }
    len = std::sqrt(len);
    for (double c : d) r.direction.push_back(static_cast<int16_t>(std::lround(c / len * 16383)));
    r.geometry.push_back(i % 11 == 0 ? 0 : (i % 5 == 0 ? 0xffffffffu : g(*rng)));
  }
  std::vector<uint16_t> albedo(static_cast<size_t>(n) * 3);
  std::uniform_int_distribution<int> a(0, 65535);
  for (uint16_t& v : albedo) v = static_cast<uint16_t>(a(*rng));
  r.rho.resize(albedo.size());
  ReflectanceOverPiQ32(albedo.data(), static_cast<uint32_t>(albedo.size()), r.rho.data());
  const DirectReceivers rx{r.direction.data(), r.geometry.data(), scale, n};
  PrepareDirectPoints(rx, &r.points);
  return r;
}

std::vector<int64_t> MakeLid(int m, std::mt19937_64* rng) {
  std::uniform_int_distribution<int64_t> cd(0, bake_format::kMaxCandelaRaw);
  std::vector<int64_t> lid(static_cast<size_t>(m) + 1);
  for (int64_t& v : lid) v = cd(*rng);
  lid[0] = bake_format::kMaxCandelaRaw;  // the steepest fall the format allows
  if (m > 1) lid[1] = 0;
  if (m > 3) lid[static_cast<size_t>(m) / 2] = 0;  // and a zero inside the beam
  return lid;
}

TEST(DirectAimedSimd, GammaTableRises) {
  // The vector body forms b - a of neighbouring entries in 32 bits.
  const GammaTable& t = SharedGammaTable();
  for (int i = 1; i < kGammaEntries; ++i) ASSERT_GE(t.bam[i], t.bam[i - 1]) << "entry " << i;
}

// Both bodies against the scalar path: AVX2 (the level capped there) and
// AVX-512 (uncapped, where the CPU has it).
TEST(DirectAimedSimd, WritesTheScalarPathsBits) {
  if (!DirectAimedHasAvx2()) GTEST_SKIP() << "this CPU has no AVX2: only the scalar path runs";
  const bool has_avx512 = DirectAimedHasAvx512();
  if (!has_avx512) std::printf("  no AVX-512 CD/DQ here: the AVX2 body only\n");
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::uniform_int_distribution<int32_t> any(INT32_MIN, INT32_MAX);
  int64_t lit = 0, compared = 0, receivers = 0, vector_receivers[2] = {0, 0};
  // Scales whose shifts span the vector bodies' range of e_shift.
  const QuantScale scales[] = {{1 << 29, -60}, {1 << 29, -40}, {1 << 20, -80}, {1 << 30, -20}};
  for (int m : {1, 7, 180, 720}) {
    for (const QuantScale& scale : scales) {
      for (uint32_t n : {1003u, 4096u}) {
        const double pan = angle(rng), tilt = angle(rng) / 2;
        const double axis_f[3] = {std::cos(tilt) * std::cos(pan), std::cos(tilt) * std::sin(pan), std::sin(tilt)};
        int32_t axis[3];
        for (int c = 0; c < 3; ++c) axis[c] = static_cast<int32_t>(std::lround(axis_f[c] * (1 << 30)));
        const Receivers r = MakeReceivers(n, axis_f, scale, &rng);
        const std::vector<int64_t> lid = MakeLid(m, &rng);
        for (const uint32_t* rho : {r.rho.data(), static_cast<const uint32_t*>(nullptr)}) {
          for (DirectStore store : {DirectStore::kWrite, DirectStore::kAdd}) {
            std::vector<int32_t> start(static_cast<size_t>(n) * 3);
            for (size_t i = 0; i < start.size(); ++i) {
              start[i] = i % 4 == 0 ? INT32_MAX - static_cast<int32_t>(i) : (i % 4 == 1 ? any(rng) : 77);
            }
            std::vector<int32_t> scalar_out = start;
            {
              const LevelCap scalar(SimdLevel::kScalar);
              DirectLightAimedQ12(r.points, SharedGammaTable(), axis, lid.data(), m, rho, store, scalar_out.data());
            }
            receivers += n;
            for (int body = 0; body < (has_avx512 ? 2 : 1); ++body) {
              std::vector<int32_t> vector_out = start;
              {
                const LevelCap cap(body == 0 ? SimdLevel::kAvx2 : SimdLevel::kAvx512Vnni);
                vector_receivers[body] += DirectLightAimedQ12(r.points, SharedGammaTable(), axis, lid.data(), m, rho,
                                                              store, vector_out.data());
              }
              for (size_t i = 0; i < start.size(); ++i) {
                ASSERT_EQ(vector_out[i], scalar_out[i])
                    << (body == 0 ? "AVX2" : "AVX-512") << " value " << i << " M " << m << " scale 2^"
                    << scale.exponent << " n " << n << (rho != nullptr ? " luminance" : " lux")
                    << (store == DirectStore::kAdd ? " add" : " write");
              }
            }
            for (size_t i = 0; i < start.size(); ++i) lit += scalar_out[i] != start[i] ? 1 : 0;
            compared += static_cast<int64_t>(start.size());
          }
        }
      }
    }
  }
  std::printf("  %lld of %lld values changed by the light, all the same bits; vector bodies did %lld (AVX2) and "
              "%lld (AVX-512) of %lld receivers\n",
              static_cast<long long>(lit), static_cast<long long>(compared), static_cast<long long>(vector_receivers[0]),
              static_cast<long long>(vector_receivers[1]), static_cast<long long>(receivers));
  EXPECT_GT(lit, compared / 10);  // the comparison must cover lit receivers
  EXPECT_GT(vector_receivers[0], receivers / 2);  // and receivers the vector bodies did
  if (has_avx512) {
    EXPECT_GT(vector_receivers[1], receivers / 2);
  }
}

}  // namespace
}  // namespace relight
