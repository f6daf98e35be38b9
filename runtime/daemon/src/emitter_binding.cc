#include "relight/control/emitter_binding.h"

#include <cmath>
#include <cstdio>

namespace relight::control {
namespace {

// Round-to-nearest a * b >> 16 for Q16.16 operands (|a|, |b| < 2^31: the product fits int64).
int64_t MulQ16(int64_t a, int64_t b) {
  const int64_t p = a * b;
  return p >= 0 ? (p + 32768) >> 16 : -((-p + 32768) >> 16);
}

// lo + level (hi - lo), level Q1.15 in 0..32767.
int64_t Lerp(const int32_t range[2], int32_t level_q15) {
  return range[0] + (int64_t{range[1]} - range[0]) * level_q15 / 32767;
}

struct Vec {
  double x = 0, y = 0, z = 0;
};
Vec Sub(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec Cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double Dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec Scale(Vec a, double s) { return {a.x * s, a.y * s, a.z * s}; }
Vec Unit(Vec a) { return Scale(a, 1.0 / std::sqrt(Dot(a, a))); }

// The unit normal of `surface`: its largest triangle's (a sliver's would be noise).
bool SurfaceNormal(const BakeMesh& mesh, uint32_t surface, Vec* n) {
  double best = 0;
  for (uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    if (mesh.triangle_surface[t] != surface) continue;
    Vec p[3];
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.triangles[3 * t + static_cast<uint32_t>(k)];
      p[k] = {mesh.positions[3 * v] / 65536.0, mesh.positions[3 * v + 1] / 65536.0, mesh.positions[3 * v + 2] / 65536.0};
    }
    const Vec c = Cross(Sub(p[1], p[0]), Sub(p[2], p[0]));
    if (Dot(c, c) > best) {
      best = Dot(c, c);
      *n = c;
    }
  }
  if (best <= 0) return false;
  *n = Unit(*n);
  return true;
}

// u along world x (y on a wall facing x), v along world z (y on a floor or
// ceiling), both made orthogonal to n and to each other.
void PlaneAxes(Vec n, Vec* u, Vec* v) {
  const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
  const Vec a = ax >= ay && ax >= az ? Vec{0, 1, 0} : Vec{1, 0, 0};
  const Vec b = az >= ax && az >= ay ? Vec{0, 1, 0} : Vec{0, 0, 1};
  *u = Unit(Sub(a, Scale(n, Dot(a, n))));
  const Vec bn = Sub(b, Scale(n, Dot(b, n)));
  *v = Unit(Sub(bn, Scale(*u, Dot(bn, *u))));
}

void ToQ16(Vec a, int32_t out[3]) {
  out[0] = static_cast<int32_t>(std::lround(a.x * 65536.0));
  out[1] = static_cast<int32_t>(std::lround(a.y * 65536.0));
  out[2] = static_cast<int32_t>(std::lround(a.z * 65536.0));
}

}  // namespace

void EmitterBinding::Shape(Bound& b, int32_t x_q15, int32_t y_q15, int32_t size_q15) {
  const int64_t du = Lerp(b.x_range_q16, x_q15), dv = Lerp(b.y_range_q16, y_q15);
  const int64_t scale = Lerp(b.size_range_q16, size_q15);
  for (int k = 0; k < b.corner_count; ++k) {
    for (int i = 0; i < 3; ++i) {
      const int64_t c = b.centre_q16[i] + MulQ16(du, b.u_q16[i]) + MulQ16(dv, b.v_q16[i]) +
                        MulQ16(scale, b.base_q16[k][i]);
      b.shape.corners_q16[k][i] = static_cast<int32_t>(c);  // |c| < 2^31: the patch keeps points within 30 km
    }
  }
  b.shape.corner_count = b.corner_count;
}

void EmitterBinding::Luminance(const Bound& b, LightQ12 out[3]) {
  const int64_t dimmer = b.level[static_cast<int>(Param::kDimmer)];
  const int rgb[3] = {static_cast<int>(Param::kRed), static_cast<int>(Param::kGreen), static_cast<int>(Param::kBlue)};
  for (int c = 0; c < 3; ++c) {
    // L (< 2^31) x dimmer x colour (each <= 2^15): < 2^61, fits int64.
    const int64_t v = int64_t{b.luminance_q12[c]} * dimmer * b.level[rgb[c]] / (int64_t{32767} * 32767);
    out[c] = LightQ12::FromRaw(static_cast<int32_t>(v));
  }
}

Status EmitterBinding::Bind(Engine* engine, const std::vector<hal::EmitterPatch>& emitters, const std::string& where) {
  engine_ = engine;
  bound_.clear();
  engine_calls_ = 0;
  for (int slot = 0; slot < kMaxSurfaceEmitters; ++slot) {
    // An older binding's emitters go (a patch reload); a bake without a hierarchy has none to remove.
    if (Status st = engine->RemoveSurfaceEmitter(slot); !st.ok() && st.code() != StatusCode::kUnsupported) return st;
  }
  const BakeMesh& mesh = engine->bake().mesh;
  for (const hal::EmitterPatch& e : emitters) {
    const std::string what = where + ":" + std::to_string(e.control.line) + ": emitter '" + e.control.name + "'";
    uint32_t surface = 0;
    while (surface < mesh.surface_names.size() && mesh.surface_names[surface] != e.surface) ++surface;
    Vec n;
    if (surface == mesh.surface_names.size() || !SurfaceNormal(mesh, surface, &n)) {
      std::string list;
      for (const std::string& s : mesh.surface_names) list += (list.empty() ? "" : ", ") + s;
      return Status(StatusCode::kNotFound, what + ": no surface '" + e.surface + "' in the bake (it has: " + list + ")");
    }
    Bound b;
    b.shape.surface = e.surface;
    Vec u, v;
    PlaneAxes(n, &u, &v);
    ToQ16(u, b.u_q16);
    ToQ16(v, b.v_q16);
    if (e.polygon_q16.empty()) {
      const int64_t hw = e.width_q16 / 2, hh = e.height_q16 / 2;
      const int sign[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      b.corner_count = 4;
      for (int k = 0; k < 4; ++k) {
        for (int i = 0; i < 3; ++i) {
          b.base_q16[k][i] = static_cast<int32_t>(MulQ16(sign[k][0] * hw, b.u_q16[i]) + MulQ16(sign[k][1] * hh, b.v_q16[i]));
        }
      }
      for (int i = 0; i < 3; ++i) b.centre_q16[i] = e.centre_q16[static_cast<size_t>(i)];
    } else {
      // About the corners' mean, inside a convex polygon: size scales about it.
      b.corner_count = static_cast<int>(e.polygon_q16.size());
      for (int i = 0; i < 3; ++i) {
        int64_t sum = 0;
        for (const auto& c : e.polygon_q16) sum += c[static_cast<size_t>(i)];
        b.centre_q16[i] = static_cast<int32_t>(sum / b.corner_count);
        for (int k = 0; k < b.corner_count; ++k) {
          b.base_q16[k][i] = e.polygon_q16[static_cast<size_t>(k)][static_cast<size_t>(i)] - b.centre_q16[i];
        }
      }
    }
    for (int c = 0; c < 3; ++c) b.luminance_q12[c] = e.luminance_q12[c];
    for (int i = 0; i < 2; ++i) {
      b.x_range_q16[i] = e.x_range_q16[i];
      b.y_range_q16[i] = e.y_range_q16[i];
      b.size_range_q16[i] = e.size_range_q16[i];
    }
    b.level[static_cast<int>(Param::kDimmer)] = e.dimmer_q15;
    b.level[static_cast<int>(Param::kRed)] = e.rgb_q15[0];
    b.level[static_cast<int>(Param::kGreen)] = e.rgb_q15[1];
    b.level[static_cast<int>(Param::kBlue)] = e.rgb_q15[2];
    b.level[static_cast<int>(Param::kX)] = e.x_q15;
    b.level[static_cast<int>(Param::kY)] = e.y_q15;
    b.level[static_cast<int>(Param::kSize)] = e.size_q15;

    // The four extremes of x, y at the largest size; removed again, solved never.
    const int32_t big = b.size_range_q16[1] >= b.size_range_q16[0] ? 32767 : 0;
    const int slot = static_cast<int>(bound_.size());
    const LightQ12 dark[3] = {};
    for (int corner = 0; corner < 4; ++corner) {
      const int32_t x = (corner & 1) ? 32767 : 0, y = (corner & 2) ? 32767 : 0;
      Shape(b, x, y, big);
      const Status st = engine->SetSurfaceEmitter(slot, b.shape, dark);
      if (!st.ok()) {
        char at[160];
        std::snprintf(at, sizeof at, " at x = %d, y = %d, size = %d (its ranges' ends)", x / 32767, y / 32767,
                      big / 32767);
        return Status(st.code(), what + at + ": " + st.message());
      }
      RELIGHT_RETURN_IF_ERROR(engine->RemoveSurfaceEmitter(slot));
    }
    bound_.push_back(b);
  }
  return Status::Ok();
}

bool EmitterBinding::Set(int index, Param param, int32_t level_q15) {
  if (index < 0 || index >= count() || !IsEmitterParam(param)) return false;
  Bound& b = bound_[static_cast<size_t>(index)];
  const int32_t level = level_q15 < 0 ? 0 : level_q15 > 32767 ? 32767 : level_q15;
  int32_t& slot = b.level[static_cast<int>(param)];
  if (slot == level) return true;
  slot = level;
  if (param == Param::kX || param == Param::kY || param == Param::kSize) {
    b.geometry_dirty = true;
  } else {
    b.luminance_dirty = true;
  }
  return true;
}

int EmitterBinding::Flush(Status* error) {
  int failed = 0;
  for (size_t i = 0; i < bound_.size(); ++i) {
    Bound& b = bound_[i];
    if (!b.geometry_dirty && !b.luminance_dirty) continue;
    const int slot = static_cast<int>(i);
    const bool on = b.level[static_cast<int>(Param::kDimmer)] > 0;
    Status st;
    if (!on) {
      if (b.placed) {
        st = engine_->RemoveSurfaceEmitter(slot);
        ++engine_calls_;
      }
      b.placed = false;
    } else {
      LightQ12 lum[3];
      Luminance(b, lum);
      if (b.geometry_dirty || !b.placed) {
        Shape(b, b.level[static_cast<int>(Param::kX)], b.level[static_cast<int>(Param::kY)],
              b.level[static_cast<int>(Param::kSize)]);
        st = engine_->SetSurfaceEmitter(slot, b.shape, lum);
        b.placed = st.ok();
      } else {
        st = engine_->SetSurfaceEmitterLuminance(slot, lum);
      }
      ++engine_calls_;
    }
    // Off, an emitter keeps its dirty geometry for when it comes on again.
    b.luminance_dirty = false;
    if (on) b.geometry_dirty = false;
    if (!st.ok()) {
      if (failed++ == 0 && error != nullptr) *error = st;
    }
  }
  return failed;
}

}  // namespace relight::control
