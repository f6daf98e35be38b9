// Float64 helpers shared by the engine's tests (recombine, direct, engine):
// the bake's quantisation convention done independently of the baker, the
// LID as float samples, small vector math.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "relight/baker/photometry.h"
#include "relight/base/fixed.h"

namespace relight::testing {

using baker::Vec3;

inline constexpr double kPi = 3.14159265358979323846;

// real = mantissa * 2^(exponent - 30), mantissa in [2^29, 2^30) (bake.h).
inline QuantScale ToQuantScale(double real_per_lsb) {
  if (!(real_per_lsb > 0)) return QuantScale{};
  int e = 0;
  const double f = std::frexp(real_per_lsb, &e);  // f in [0.5, 1)
  int64_t m = std::llround(f * 1073741824.0);
  if (m == (int64_t{1} << 30)) {
    m >>= 1;
    ++e;
  }
  return QuantScale{static_cast<int32_t>(m), e};
}
inline double ScaleValue(QuantScale s) { return std::ldexp(double(s.mantissa), s.exponent - 30); }

// Quantises count values v[i * stride] to int16 with one scale (max |v| ->
// 32767), writing out[i * out_stride].
inline QuantScale QuantiseInt16(const double* v, size_t count, size_t stride, int16_t* out,
                                size_t out_stride) {
  double max_abs = 0;
  for (size_t i = 0; i < count; ++i) max_abs = std::max(max_abs, std::fabs(v[i * stride]));
  const QuantScale s = ToQuantScale(max_abs / 32767.0);
  const double step = ScaleValue(s);
  for (size_t i = 0; i < count; ++i) {
    const double q = step > 0 ? std::round(v[i * stride] / step) : 0.0;
    out[i * out_stride] = static_cast<int16_t>(std::clamp(q, -32767.0, 32767.0));
  }
  return s;
}

inline QuantScale QuantiseUint32(const std::vector<double>& v, std::vector<uint32_t>* out) {
  double max_v = 0;
  for (double x : v) max_v = std::max(max_v, x);
  const QuantScale s = ToQuantScale(max_v / 4294967295.0);
  const double step = ScaleValue(s);
  out->resize(v.size());
  for (size_t i = 0; i < v.size(); ++i) {
    (*out)[i] = step > 0 ? static_cast<uint32_t>(std::clamp(std::round(v[i] / step), 0.0,
                                                            4294967295.0))
                         : 0u;
  }
  return s;
}

// cos^exponent beam, zero past 90 degrees, at M+1 samples 0..180 degrees (cd).
inline std::vector<double> CosPowerSamples(double peak_cd, double exponent, int M) {
  std::vector<double> s(M + 1);
  for (int k = 0; k <= M; ++k) {
    const double c = std::cos(kPi * k / M);
    s[k] = c > 0 ? peak_cd * std::pow(c, exponent) : 0.0;
  }
  return s;
}

// The samples as the bake stores them (Q48.16 cd) and back.
inline std::vector<int64_t> ToQ16(const std::vector<double>& cd) {
  std::vector<int64_t> q(cd.size());
  for (size_t i = 0; i < cd.size(); ++i) q[i] = std::llround(cd[i] * 65536.0);
  return q;
}
inline std::vector<double> FromQ16(const std::vector<int64_t>& q) {
  std::vector<double> cd(q.size());
  for (size_t i = 0; i < q.size(); ++i) cd[i] = double(q[i]) / 65536.0;
  return cd;
}

// Linear interpolation of M+1 uniform samples at gamma (degrees, 0..180).
inline double LinearLid(const std::vector<double>& samples, double gamma_deg) {
  const int M = static_cast<int>(samples.size()) - 1;
  const double pos = std::clamp(gamma_deg, 0.0, 180.0) / 180.0 * M;
  const int i = std::min(static_cast<int>(pos), M - 1);
  const double f = pos - i;
  return samples[i] + (samples[i + 1] - samples[i]) * f;
}

inline double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 Sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline double Norm(const Vec3& a) { return std::sqrt(Dot(a, a)); }
inline Vec3 Normalised(const Vec3& a) {
  const double n = Norm(a);
  return {a[0] / n, a[1] / n, a[2] / n};
}
// Angle between two directions of any length, degrees (atan2 form: accurate
// near 0 and 180).
inline double AngleDeg(const Vec3& a, const Vec3& b) {
  const Vec3 c = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  return std::atan2(Norm(c), Dot(a, b)) * 180.0 / kPi;
}

}  // namespace relight::testing
