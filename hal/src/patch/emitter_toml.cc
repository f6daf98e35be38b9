// [[emitter]] in a patch: a run-time light source on a surface, its shape,
// luminance, the ranges its x, y and size levels span, and its input
// controls (as a fixture's). Numbers only: what a surface is, hal does not
// know (the control stage checks the shape against the bake).
#include <cmath>
#include <cstdint>
#include <string>

#include "relight/hal/patch.h"
#include "toml_table.h"

namespace relight::hal::patch_reader {
namespace {

// dimmer, x, y, size, then the colour bytes: position and size take whole
// 16-bit registers, as a dimmer does.
RegisterLayout EmitterLayout() {
  RegisterLayout layout;
  const bool ok = RegisterLayout::FromChannels({Channel::kDimmer, Channel::kX, Channel::kY, Channel::kSize,
                                                Channel::kRed, Channel::kGreen, Channel::kBlue},
                                               &layout, nullptr);
  (void)ok;  // a valid list
  return layout;
}

int32_t MetresQ16(double m) { return static_cast<int32_t>(std::llround(m * 65536.0)); }
int32_t LevelQ15(double level) { return static_cast<int32_t>(std::lround(level * 32767.0)); }

// `n` numbers in lo..hi from an array node; `what` says what was expected.
void Numbers(const Table& t, const toml::node* node, int n, double lo, double hi, const std::string& what,
             double* out) {
  const toml::array* arr = node != nullptr ? node->as_array() : nullptr;
  if (arr == nullptr || static_cast<int>(arr->size()) != n) t.Fail(node, what);
  for (int i = 0; i < n; ++i) {
    const toml::node& item = *arr->get(static_cast<size_t>(i));
    if (!item.is_number()) t.Fail(&item, what);
    out[i] = *item.value<double>();
    if (!std::isfinite(out[i]) || out[i] < lo || out[i] > hi) t.Fail(&item, what);
  }
}

// A point in the room: metres, within +-30000 (Q16.16 holds +-32768).
std::array<int32_t, 3> Point(const Table& t, const toml::node* node, const std::string& what) {
  double v[3];
  Numbers(t, node, 3, -30000, 30000, what + " must be [x, y, z] in metres", v);
  return {MetresQ16(v[0]), MetresQ16(v[1]), MetresQ16(v[2])};
}

// [lo, hi] -> Q16.16; `what` names the key in messages.
void Range(const Table& t, const char* key, double lo, double hi, const char* unit, int32_t out[2]) {
  const toml::node* node = t.Node(key);
  if (node == nullptr) return;
  double v[2];
  char why[200];
  std::snprintf(why, sizeof why, "'%s' must be [from, to], each in %g..%g%s", key, lo, hi, unit);
  Numbers(t, node, 2, lo, hi, why, v);
  out[0] = MetresQ16(v[0]);
  out[1] = MetresQ16(v[1]);
}

// The level a range gives `value` (clamped to 0..1); 0 for an empty range.
int32_t LevelOf(const int32_t range[2], int32_t value) {
  if (range[0] == range[1]) return 0;
  const int64_t num = (int64_t{value} - range[0]) * 32767;
  const int64_t level = num / (int64_t{range[1]} - range[0]);
  return static_cast<int32_t>(level < 0 ? 0 : level > 32767 ? 32767 : level);
}

}  // namespace

void ParseEmitter(const Table& t, Patch* patch) {
  t.CheckKeys({"name", "surface", "centre", "width", "height", "polygon", "luminance", "x_range_m", "y_range_m",
               "size_range", "dimmer", "colour", "x", "y", "size", "modbus_base", "registers", "dimmer_curve",
               "fade_ms"});
  EmitterPatch e;
  e.control.line = t.line();
  e.control.emitter = static_cast<int>(patch->emitters.size());
  ParseName(t, &e.control.name);
  ParseControls(t, EmitterLayout(), &e.control);
  e.surface = t.String("surface", "", true);

  const bool rect = t.Has("centre"), poly = t.Has("polygon");
  if (rect == poly) {
    t.Fail(nullptr, "needs either a rectangle (centre, width, height) or a polygon = [[x, y, z], ...], not "
                    + std::string(rect ? "both" : "neither"));
  }
  if (rect) {
    e.centre_q16 = Point(t, t.Node("centre"), "'centre'");
    if (!t.Has("width") || !t.Has("height")) t.Fail(nullptr, "a rectangle needs 'width' and 'height' (metres)");
    e.width_q16 = MetresQ16(t.Number("width", 0, 0.001, 100, " m"));
    e.height_q16 = MetresQ16(t.Number("height", 0, 0.001, 100, " m"));
  } else {
    if (t.Has("width") || t.Has("height")) t.Fail(t.Node("width") ? t.Node("width") : t.Node("height"),
                                                   "'width' and 'height' go with 'centre', not 'polygon'");
    const toml::array* corners = t.Array("polygon");
    if (corners->size() < 3 || corners->size() > static_cast<size_t>(kMaxPatchEmitterCorners)) {
      t.Fail(t.Node("polygon"), "'polygon' needs 3.." + std::to_string(kMaxPatchEmitterCorners) + " corners, got " +
                                    std::to_string(corners->size()));
    }
    for (const toml::node& c : *corners) e.polygon_q16.push_back(Point(t, &c, "each polygon corner"));
  }

  const toml::node* lum = t.Node("luminance");
  if (lum == nullptr) t.Fail(nullptr, "missing 'luminance' (cd/m^2, a number or [R, G, B])");
  double rgb[3];
  if (lum->is_number()) {
    rgb[0] = rgb[1] = rgb[2] = *lum->value<double>();
    if (!std::isfinite(rgb[0]) || rgb[0] < 0 || rgb[0] > 500000) {
      t.Fail(lum, "'luminance' must be in 0..500000 cd/m^2");
    }
  } else {
    Numbers(t, lum, 3, 0, 500000, "'luminance' must be a number or [R, G, B], each in 0..500000 cd/m^2", rgb);
  }
  for (int c = 0; c < 3; ++c) e.luminance_q12[c] = static_cast<int32_t>(std::llround(rgb[c] * 4096.0));

  Range(t, "x_range_m", -100, 100, " m", e.x_range_q16);
  Range(t, "y_range_m", -100, 100, " m", e.y_range_q16);
  Range(t, "size_range", 0.01, 100, "", e.size_range_q16);
  // Start where the offsets are 0 (or as close as the ranges allow), at the size scale 1.
  e.x_q15 = LevelOf(e.x_range_q16, 0);
  e.y_q15 = LevelOf(e.y_range_q16, 0);
  e.size_q15 = e.size_range_q16[0] == e.size_range_q16[1] ? 32767 : LevelOf(e.size_range_q16, 65536);
  if (t.Has("x")) e.x_q15 = LevelQ15(t.Number("x", 0, 0, 1));
  if (t.Has("y")) e.y_q15 = LevelQ15(t.Number("y", 0, 0, 1));
  if (t.Has("size")) e.size_q15 = LevelQ15(t.Number("size", 0, 0, 1));
  e.dimmer_q15 = LevelQ15(t.Number("dimmer", 1, 0, 1));
  if (t.Has("colour")) {
    double c[3];
    Numbers(t, t.Node("colour"), 3, 0, 1, "'colour' must be [R, G, B], each in 0..1", c);
    for (int i = 0; i < 3; ++i) e.rgb_q15[i] = LevelQ15(c[i]);
  }

  if (patch->emitters.size() >= static_cast<size_t>(kMaxPatchEmitters)) {
    t.Fail(nullptr, "more than " + std::to_string(kMaxPatchEmitters) + " emitters (the engine holds " +
                        std::to_string(kMaxPatchEmitters) + ")");
  }
  for (const EmitterPatch& other : patch->emitters) {
    if (other.control.name == e.control.name) {
      t.Fail(nullptr, "emitter '" + e.control.name + "' is patched twice (first at line " +
                          std::to_string(other.control.line) + ")");
    }
  }
  patch->emitters.push_back(std::move(e));
}

}  // namespace relight::hal::patch_reader
