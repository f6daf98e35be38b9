#include "relight/bake/bake_check.h"

#include <cstddef>

#include "bake_format.h"
#include "relight/base/sh_index.h"
#include "relight/base/status.h"

namespace relight::bake_format {
namespace {

using ull = unsigned long long;

bool IsUnitQ14(int16_t x, int16_t y, int16_t z) {
  const int64_t sq = int64_t{x} * x + int64_t{y} * y + int64_t{z} * z;  // Q2.28
  const int64_t off = sq - kUnitSquared;
  return off <= kUnitSquaredTolerance && off >= -kUnitSquaredTolerance;
}

std::string NotUnit(const char* what, size_t index, const std::vector<int16_t>& v) {
  return StrFormat("%s %llu: (%d, %d, %d) is not a unit vector in Q1.14", what,
                   static_cast<ull>(index), v[3 * index], v[3 * index + 1], v[3 * index + 2]);
}

std::string CheckLevelQ15(int16_t v, const char* what) {
  if (v < 0) return StrFormat("%s %d is outside [0, 32767] (Q1.15)", what, v);
  return "";
}

}  // namespace

std::string CountMismatch(const char* what, size_t have, const char* expected_how,
                          uint64_t expected) {
  return StrFormat("%s has %llu values, expected %s = %llu", what, static_cast<ull>(have),
                   expected_how, static_cast<ull>(expected));
}

std::string CheckName(const std::string& name, bool allow_empty) {
  if (name.empty()) return allow_empty ? "" : "name is empty";
  if (name.size() > kMaxNameBytes) {
    return StrFormat("name is %llu bytes, more than %u", static_cast<ull>(name.size()),
                     kMaxNameBytes);
  }
  const auto* s = reinterpret_cast<const uint8_t*>(name.data());
  const size_t n = name.size();
  size_t i = 0;
  while (i < n) {
    const uint8_t lead = s[i];
    uint32_t cp = lead;
    size_t len = 1;
    if (lead >= 0x80) {
      if ((lead & 0xE0) == 0xC0) {
        cp = lead & 0x1Fu, len = 2;
      } else if ((lead & 0xF0) == 0xE0) {
        cp = lead & 0x0Fu, len = 3;
      } else if ((lead & 0xF8) == 0xF0) {
        cp = lead & 0x07u, len = 4;
      } else {
        return StrFormat("name is not UTF-8 (byte %llu)", static_cast<ull>(i));
      }
      if (len > n - i) return StrFormat("name is not UTF-8 (byte %llu)", static_cast<ull>(i));
      for (size_t k = 1; k < len; ++k) {
        if ((s[i + k] & 0xC0) != 0x80) {
          return StrFormat("name is not UTF-8 (byte %llu)", static_cast<ull>(i + k));
        }
        cp = cp << 6 | (s[i + k] & 0x3Fu);
      }
      // Overlong forms, surrogates and code points past U+10FFFF are not UTF-8.
      constexpr uint32_t kShortest[5] = {0, 0, 0x80, 0x800, 0x10000};
      if (cp < kShortest[len] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) {
        return StrFormat("name is not UTF-8 (byte %llu)", static_cast<ull>(i));
      }
    }
    if (cp < 0x20 || (cp >= 0x7F && cp < 0xA0)) {
      return StrFormat("name has control character U+%04X at byte %llu", cp, static_cast<ull>(i));
    }
    i += len;
  }
  return "";
}

std::string CheckScale(QuantScale scale) {
  if (scale.mantissa == 0) {
    if (scale.exponent != 0) return StrFormat("zero scale has exponent %d, not 0", scale.exponent);
    return "";
  }
  if (scale.mantissa < kScaleMantissaMin || scale.mantissa >= kScaleMantissaEnd) {
    return StrFormat("mantissa %d is outside [2^29, 2^30) and not 0", scale.mantissa);
  }
  if (scale.exponent < kMinScaleExponent || scale.exponent > kMaxScaleExponent) {
    return StrFormat("exponent %d is outside [%d, %d]", scale.exponent, kMinScaleExponent,
                     kMaxScaleExponent);
  }
  return "";
}

std::string CheckCounts(uint64_t vertices, uint64_t triangles, uint64_t surfaces, uint64_t grids,
                        uint64_t luminaires) {
  struct Limit {
    const char* what;
    uint64_t value, max;
  };
  const Limit limits[] = {{"vertex count", vertices, kMaxVertices},
                          {"triangle count", triangles, kMaxTriangles},
                          {"surface count", surfaces, kMaxSurfaces},
                          {"grid count", grids, kMaxGrids},
                          {"luminaire count", luminaires, kMaxLuminaires}};
  for (const Limit& l : limits) {
    if (l.value > l.max) {
      return StrFormat("%s %llu exceeds the limit %llu", l.what, static_cast<ull>(l.value),
                       static_cast<ull>(l.max));
    }
  }
  return "";
}

std::string CheckGridPointCount(uint64_t points) {
  if (points > kMaxGridPoints) {
    return StrFormat("point count %llu exceeds the limit %u", static_cast<ull>(points),
                     kMaxGridPoints);
  }
  return "";
}

std::string CheckSceneHeader(const Bake& bake) {
  std::string e = CheckName(bake.scene_name, /*allow_empty=*/true);
  if (!e.empty()) return "scene name: " + e;
  if (bake.white_luminance <= 0) {
    return StrFormat("white luminance %d is not positive (LightQ12 cd/m^2)", bake.white_luminance);
  }
  if (bake.camera.fov_y <= 0 || bake.camera.fov_y >= (180 << 16)) {
    return StrFormat("camera fov_y %d is outside (0, 180) degrees (Q16.16)", bake.camera.fov_y);
  }
  return "";
}

std::string CheckMesh(const BakeMesh& mesh) {
  const size_t n = mesh.positions.size();
  if (n % 3 != 0) return CountMismatch("positions", n, "a multiple of 3", n - n % 3);
  const uint64_t v = n / 3;
  if (mesh.normals.size() != n) {
    return CountMismatch("normals", mesh.normals.size(), "3 x vertices", n);
  }
  if (mesh.albedo.size() != n) {
    return CountMismatch("albedo", mesh.albedo.size(), "3 x vertices", n);
  }
  const size_t tn = mesh.triangles.size();
  if (tn % 3 != 0) return CountMismatch("triangles", tn, "a multiple of 3", tn - tn % 3);
  const uint64_t t = tn / 3;
  if (mesh.triangle_surface.size() != t) {
    return CountMismatch("triangle_surface", mesh.triangle_surface.size(), "triangles", t);
  }
  const uint64_t s = mesh.surface_names.size();
  for (size_t i = 0; i < tn; ++i) {
    if (mesh.triangles[i] >= v) {
      return StrFormat("triangle %llu: vertex index %u >= vertex count %llu",
                       static_cast<ull>(i / 3), mesh.triangles[i], static_cast<ull>(v));
    }
  }
  for (size_t i = 0; i < t; ++i) {
    if (mesh.triangle_surface[i] >= s) {
      return StrFormat("triangle %llu: surface index %u >= surface count %llu", static_cast<ull>(i),
                       mesh.triangle_surface[i], static_cast<ull>(s));
    }
  }
  for (size_t i = 0; i < v; ++i) {
    if (!IsUnitQ14(mesh.normals[3 * i], mesh.normals[3 * i + 1], mesh.normals[3 * i + 2])) {
      return NotUnit("vertex normal", i, mesh.normals);
    }
  }
  for (size_t i = 0; i < s; ++i) {
    const std::string e = CheckName(mesh.surface_names[i], /*allow_empty=*/true);
    if (!e.empty()) return StrFormat("surface %llu: %s", static_cast<ull>(i), e.c_str());
  }
  return "";
}

std::string CheckGrid(const BakeGrid& grid) {
  std::string e = CheckName(grid.name, /*allow_empty=*/false);
  if (!e.empty()) return e;
  const size_t n = grid.points.size();
  if (n % 3 != 0) return CountMismatch("points", n, "a multiple of 3", n - n % 3);
  if (grid.normals.size() != n) {
    return CountMismatch("normals", grid.normals.size(), "3 x points", n);
  }
  const uint64_t p = n / 3;
  e = CheckGridPointCount(p);
  if (!e.empty()) return e;
  const bool list = grid.columns == 0 && grid.rows == 0;
  const uint64_t cells = uint64_t{grid.columns} * grid.rows;
  if (!list && (cells == 0 || cells != p)) {
    return StrFormat("columns x rows = %u x %u, but %llu points (use 0 x 0 for a list)",
                     grid.columns, grid.rows, static_cast<ull>(p));
  }
  for (size_t i = 0; i < p; ++i) {
    if (!IsUnitQ14(grid.normals[3 * i], grid.normals[3 * i + 1], grid.normals[3 * i + 2])) {
      return NotUnit("point normal", i, grid.normals);
    }
  }
  return "";
}

std::string CheckLuminaire(const BakeLuminaire& lum) {
  std::string e = CheckName(lum.name, /*allow_empty=*/false);
  if (!e.empty()) return e;
  const auto mounting = static_cast<unsigned>(lum.mounting);
  if (mounting > static_cast<unsigned>(Mounting::kWall)) {
    return StrFormat("mounting %u is not 0 (hanging), 1 (standing) or 2 (wall)", mounting);
  }
  const auto mode = static_cast<unsigned>(lum.direct_mode);
  if (mode > static_cast<unsigned>(DirectMode::kAllInSh)) {
    return StrFormat("direct mode %u is not 0 (exact direct) or 1 (all in SH)", mode);
  }
  if (lum.sh_degree > kMaxShDegree) {
    return StrFormat("SH degree %u exceeds the maximum %d", lum.sh_degree, kMaxShDegree);
  }
  if (lum.use_sigma > 1) return StrFormat("use_sigma %u is not 0 or 1", lum.use_sigma);
  e = CheckLevelQ15(lum.default_dimmer, "default dimmer");
  for (int c = 0; c < 3 && e.empty(); ++c) e = CheckLevelQ15(lum.default_rgb[c], "default colour");
  if (!e.empty()) return e;
  const size_t samples = lum.lid.candela.size();
  if (samples < kMinLidSamples || samples > kMaxLidSamples) {
    return StrFormat("LID has %llu samples, outside [%u, %u]", static_cast<ull>(samples),
                     kMinLidSamples, kMaxLidSamples);
  }
  for (size_t k = 0; k < samples; ++k) {
    const int64_t cd = lum.lid.candela[k];
    if (cd < 0 || cd > kMaxCandelaRaw) {
      return StrFormat("LID sample %llu: %lld (Q48.16 cd) is outside [0, 2^31 cd]",
                       static_cast<ull>(k), static_cast<long long>(cd));
    }
  }
  if (lum.yaw < -kMaxTurnRaw || lum.yaw > kMaxTurnRaw) {
    return StrFormat("yaw %d (Q16.16 degrees) is outside [-360, 360]", lum.yaw);
  }
  if (lum.roll < -kMaxTurnRaw || lum.roll > kMaxTurnRaw) {
    return StrFormat("roll %d (Q16.16 degrees) is outside [-360, 360]", lum.roll);
  }
  if (lum.pan_range <= 0 || lum.pan_range > kMaxPanRangeRaw) {
    return StrFormat("pan range %d (Q16.16 degrees) is outside (0, 720]", lum.pan_range);
  }
  if (lum.tilt_range <= 0 || lum.tilt_range > kMaxTiltRangeRaw) {
    return StrFormat("tilt range %d (Q16.16 degrees) is outside (0, 360]", lum.tilt_range);
  }
  e = CheckLidTable(lum.lid, lum.sh_degree);
  return e.empty() ? CheckZoom(lum.zoom, lum.lid) : e;
}

std::string CheckLidTable(const BakeLid& lid, int sh_degree) {
  const size_t planes = lid.c_deg.size(), gammas = lid.gamma_deg.size();
  if (planes == 0) {
    if (gammas != 0 || !lid.table.empty() || !lid.sh.empty()) {
      return "an axisymmetric LID (no C planes) has no gammas, table or SH coefficients";
    }
    return "";
  }
  if (planes < kMinLidPlanes || planes > kMaxLidPlanes || gammas < kMinLidGammas ||
      gammas > kMaxLidGammas || static_cast<uint64_t>(planes) * gammas > kMaxLidTableValues) {
    return StrFormat("LID table of %llu planes x %llu gammas is outside [%u, %u] x [%u, %u] or "
                     "above %llu values",
                     static_cast<ull>(planes), static_cast<ull>(gammas), kMinLidPlanes,
                     kMaxLidPlanes, kMinLidGammas, kMaxLidGammas,
                     static_cast<ull>(kMaxLidTableValues));
  }
  if (lid.c_deg.front() != 0 || lid.c_deg.back() != (360 << 16)) {
    return "LID C angles must run from 0 to 360 degrees";
  }
  for (size_t p = 1; p < planes; ++p) {
    if (lid.c_deg[p] <= lid.c_deg[p - 1]) {
      return StrFormat("LID C angle %llu does not increase", static_cast<ull>(p));
    }
  }
  for (size_t g = 0; g < gammas; ++g) {
    if (lid.gamma_deg[g] < 0 || lid.gamma_deg[g] > (180 << 16) ||
        (g > 0 && lid.gamma_deg[g] <= lid.gamma_deg[g - 1])) {
      return StrFormat("LID gamma angle %llu: %d (Q16.16 degrees) is outside [0, 180] or does "
                       "not increase",
                       static_cast<ull>(g), lid.gamma_deg[g]);
    }
  }
  if (lid.table.size() != planes * gammas) {
    return CountMismatch("LID table", lid.table.size(), "planes x gammas", planes * gammas);
  }
  for (size_t i = 0; i < lid.table.size(); ++i) {
    if (lid.table[i] < 0 || lid.table[i] > kMaxCandelaRaw) {
      return StrFormat("LID table value %llu: %lld (Q48.16 cd) is outside [0, 2^31 cd]",
                       static_cast<ull>(i), static_cast<long long>(lid.table[i]));
    }
  }
  for (size_t g = 0; g < gammas; ++g) {
    if (lid.table[(planes - 1) * gammas + g] != lid.table[g]) {
      return StrFormat("LID table: the plane at C 360 differs from C 0 at gamma %llu",
                       static_cast<ull>(g));
    }
  }
  const size_t terms = static_cast<size_t>(ShTermCount(sh_degree));
  if (lid.sh.size() != terms) {
    return CountMismatch("LID SH coefficients", lid.sh.size(), "(N+1)^2", terms);
  }
  for (size_t t = 0; t < terms; ++t) {
    if (lid.sh[t] < -kMaxShCoefficientRaw || lid.sh[t] > kMaxShCoefficientRaw) {
      return StrFormat("LID SH coefficient %llu: %lld (Q48.16 cd) is outside +-2^34 cd",
                       static_cast<ull>(t), static_cast<long long>(lid.sh[t]));
    }
  }
  return "";
}

std::string CheckDirect(const BakeLightReceivers& rec, DirectMode mode, uint32_t receivers) {
  if (mode == DirectMode::kAllInSh) {
    if (!rec.direction.empty() || !rec.geometry.empty()) {
      return StrFormat("direction and geometry must be empty in all-in-SH mode (have %llu, %llu)",
                       static_cast<ull>(rec.direction.size()),
                       static_cast<ull>(rec.geometry.size()));
    }
    if (rec.geometry_scale.mantissa != 0 || rec.geometry_scale.exponent != 0) {
      return "geometry_scale must be zero in all-in-SH mode";
    }
    return "";
  }
  const uint64_t n = receivers;
  if (rec.direction.size() != 3 * n) {
    return CountMismatch("direction", rec.direction.size(), "3 x receivers", 3 * n);
  }
  if (rec.geometry.size() != n) {
    return CountMismatch("geometry", rec.geometry.size(), "receivers", n);
  }
  std::string e = CheckScale(rec.geometry_scale);
  if (!e.empty()) return "geometry_scale: " + e;
  for (size_t r = 0; r < n; ++r) {
    if (rec.geometry[r] != 0 && rec.geometry_scale.mantissa == 0) {
      return StrFormat("receiver %llu: geometry %u with a zero geometry_scale", static_cast<ull>(r),
                       rec.geometry[r]);
    }
    const int16_t* d = &rec.direction[3 * r];
    // A receiver the luminaire cannot reach (geometry 0) may have no direction.
    const bool zero = d[0] == 0 && d[1] == 0 && d[2] == 0;
    if (!(zero && rec.geometry[r] == 0) && !IsUnitQ14(d[0], d[1], d[2])) {
      return NotUnit("receiver direction", r, rec.direction);
    }
  }
  return "";
}

std::string CheckBasis(const BakeLightReceivers& rec, int sh_degree, uint32_t receivers) {
  if (sh_degree < 0 || sh_degree > kMaxShDegree) {
    return StrFormat("SH degree %d exceeds the maximum %d", sh_degree, kMaxShDegree);
  }
  const uint64_t terms = static_cast<uint64_t>(ShTermCount(sh_degree));
  const uint64_t n = receivers;
  if (rec.basis_scale.size() != 3 * terms) {
    return CountMismatch("basis_scale", rec.basis_scale.size(), "3 x terms", 3 * terms);
  }
  if (rec.basis.size() != 3 * terms * n) {
    return CountMismatch("basis", rec.basis.size(), "3 x terms x receivers", 3 * terms * n);
  }
  for (size_t t = 0; t < terms; ++t) {
    for (size_t c = 0; c < 3; ++c) {
      const QuantScale scale = rec.basis_scale[3 * t + c];
      std::string e = CheckScale(scale);
      if (!e.empty()) {
        return StrFormat("basis_scale[term %llu][channel %llu]: %s", static_cast<ull>(t),
                         static_cast<ull>(c), e.c_str());
      }
      if (scale.mantissa != 0) continue;
      // A zero scale means an all-zero block (fixed.h QuantScale).
      for (size_t r = 0; r < n; ++r) {
        const int16_t q = rec.basis[(t * n + r) * 3 + c];
        if (q != 0) {
          return StrFormat("term %llu channel %llu: zero scale but receiver %llu has value %d",
                           static_cast<ull>(t), static_cast<ull>(c), static_cast<ull>(r), q);
        }
      }
    }
  }
  return "";
}

std::string CheckUniqueNames(const std::vector<const std::string*>& names, const char* kind) {
  for (size_t i = 0; i < names.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      if (*names[i] == *names[j]) {
        return StrFormat("%s %llu has the same name '%s' as %s %llu (duplicate)", kind,
                         static_cast<ull>(i), names[i]->c_str(), kind, static_cast<ull>(j));
      }
    }
  }
  return "";
}

}  // namespace relight::bake_format
