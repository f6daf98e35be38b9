#include "emitter_args.h"

#include <cmath>
#include <cstdlib>
#include <vector>

namespace relight::cli {
namespace {

// Comma-separated numbers; false on anything else.
bool ParseNumbers(const std::string& text, std::vector<double>* out) {
  out->clear();
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (item.empty() || end == item.c_str() || *end != '\0' || !std::isfinite(v)) return false;
    out->push_back(v);
    if (comma == std::string::npos) return true;
    start = comma + 1;
  }
}

}  // namespace

bool ParseEmitterArg(const std::string& text, SurfaceEmitterShape* shape, LightQ12 luminance[3],
                     std::string* error) {
  const std::string what = "--emitter '" + text + "': ";
  // The surface name may hold ':'; the luminance and corners do not.
  const size_t last = text.rfind(':');
  const size_t middle = last == std::string::npos || last == 0 ? std::string::npos : text.rfind(':', last - 1);
  if (middle == std::string::npos || middle == 0) {
    *error = what + "wants SURFACE:LUMINANCE:x,y,z;x,y,z;x,y,z[;...]";
    return false;
  }
  shape->surface = text.substr(0, middle);
  std::vector<double> l;
  if (!ParseNumbers(text.substr(middle + 1, last - middle - 1), &l) || (l.size() != 1 && l.size() != 3)) {
    *error = what + "luminance wants L or R,G,B in cd/m^2";
    return false;
  }
  for (int c = 0; c < 3; ++c) {
    const double v = l[l.size() == 1 ? 0 : static_cast<size_t>(c)];
    if (v < 0 || v > 500000) {
      *error = what + "luminance must be within 0..500000 cd/m^2";
      return false;
    }
    luminance[c] = LightQ12::FromRaw(static_cast<int32_t>(std::lround(v * 4096.0)));
  }
  const std::string corners = text.substr(last + 1);
  shape->corner_count = 0;
  size_t start = 0;
  while (start <= corners.size()) {
    const size_t semi = corners.find(';', start);
    std::vector<double> p;
    if (!ParseNumbers(corners.substr(start, semi == std::string::npos ? std::string::npos : semi - start), &p) ||
        p.size() != 3) {
      *error = what + "each corner wants x,y,z in metres";
      return false;
    }
    if (shape->corner_count == kMaxSurfaceEmitterCorners) {
      *error = what + "at most 8 corners";
      return false;
    }
    for (int i = 0; i < 3; ++i) {
      if (std::abs(p[static_cast<size_t>(i)]) >= 32767) {
        *error = what + "corner outside +-32767 m";
        return false;
      }
      shape->corners_q16[shape->corner_count][i] = static_cast<int32_t>(std::lround(p[static_cast<size_t>(i)] * 65536.0));
    }
    ++shape->corner_count;
    if (semi == std::string::npos) break;
    start = semi + 1;
  }
  return true;
}

bool ApplyEmitterText(Engine& engine, int slot, const std::string& text, std::string* error) {
  SurfaceEmitterShape shape;
  LightQ12 luminance[3];
  if (!ParseEmitterArg(text, &shape, luminance, error)) return false;
  const Status st = engine.SetSurfaceEmitter(slot, shape, luminance);
  if (!st.ok()) {
    *error = "--emitter '" + text + "': " + st.ToString();
    return false;
  }
  return true;
}

}  // namespace relight::cli
