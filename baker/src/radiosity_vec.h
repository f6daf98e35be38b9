// Small float64 vector operators for the radiosity stages. They live in their
// own namespace so they never collide with other baker files' helpers; a .cc
// file opts in with `using namespace relight::baker::radiosity_vec;`.
#pragma once

#include <cmath>

#include "relight/baker/scene.h"

namespace relight::baker::radiosity_vec {

inline Vec3 operator+(const Vec3& a, const Vec3& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}
inline Vec3 operator-(const Vec3& a, const Vec3& b) {
  return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
inline Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline Vec3& operator+=(Vec3& a, const Vec3& b) {
  a = a + b;
  return a;
}
inline double Dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Vec3 Cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline double Length(const Vec3& a) { return std::sqrt(Dot(a, a)); }
// Unit vector; the zero vector stays zero.
inline Vec3 Normalized(const Vec3& a) {
  const double len = Length(a);
  return len > 0 ? (1.0 / len) * a : Vec3{0, 0, 0};
}

}  // namespace relight::baker::radiosity_vec
