// QLC+ fixture definition (.qxf) -> FixtureType. Two channel styles occur in
// the library: QLC+ 4.12+ channel presets (<Channel Preset="PositionPan"/>)
// and the older <Group Byte="0|1">Intensity|Pan|Tilt|Colour|Shutter|Beam</Group>
// with <Colour>Red</Colour>. Errors name file:line; pugixml reports byte
// offsets, which LineAt() turns into lines.
#include <pugixml.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>

#include "fixture_types/type_common.h"
#include "relight/hal/dmx/fixture_type.h"

namespace relight::hal {
namespace {

struct QxfContext {
  const std::string& text;
  const std::string& where;
  std::string error;  // first error, "file:line: what"

  int LineAt(ptrdiff_t offset) const {
    if (offset < 0) return 0;
    const size_t end = std::min(static_cast<size_t>(offset), text.size());
    return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<ptrdiff_t>(end), '\n'));
  }
  int Line(const pugi::xml_node& n) const { return LineAt(n.offset_debug()); }
  void Fail(const pugi::xml_node& n, const std::string& what) {
    if (error.empty()) error = where + ":" + std::to_string(Line(n)) + ": " + what;
  }
};

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool Contains(const std::string& haystack_lower, const char* needle) {
  return haystack_lower.find(needle) != std::string::npos;
}

// "#rrggbb" -> colour; false if it is not one.
bool ParseHexColor(const char* s, Rgb8* out) {
  if (s == nullptr || s[0] != '#' || std::strlen(s) != 7) return false;
  unsigned v = 0;
  for (int i = 1; i < 7; ++i) {
    const int c = std::tolower(static_cast<unsigned char>(s[i]));
    int d;
    if (c >= '0' && c <= '9') d = c - '0';
    else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
    else return false;
    v = (v << 4) | static_cast<unsigned>(d);
  }
  *out = Rgb8{static_cast<uint8_t>(v >> 16), static_cast<uint8_t>(v >> 8), static_cast<uint8_t>(v)};
  return true;
}

// The colour a capability shows: Res1 (QLC+ 4.12) or Color (older); a split
// slot (Res2 / Color2) shows both halves, rendered as their mean.
bool CapabilityColor(const pugi::xml_node& cap, Rgb8* out) {
  Rgb8 a, b;
  const bool has_a = ParseHexColor(cap.attribute("Res1").value(), &a) || ParseHexColor(cap.attribute("Color").value(), &a);
  if (!has_a) return false;
  const bool has_b = ParseHexColor(cap.attribute("Res2").value(), &b) || ParseHexColor(cap.attribute("Color2").value(), &b);
  if (has_b) {
    a = Rgb8{static_cast<uint8_t>((a.r + b.r + 1) / 2), static_cast<uint8_t>((a.g + b.g + 1) / 2),
             static_cast<uint8_t>((a.b + b.b + 1) / 2)};
  }
  *out = a;
  return true;
}

// Reads Min/Max of a capability; false (and ctx.error) if malformed.
bool CapabilityRange(QxfContext& ctx, const pugi::xml_node& cap, DmxRange* out) {
  const pugi::xml_attribute lo = cap.attribute("Min"), hi = cap.attribute("Max");
  if (!lo || !hi) {
    ctx.Fail(cap, "<Capability> needs Min and Max");
    return false;
  }
  const int mn = lo.as_int(-1), mx = hi.as_int(-1);
  if (mn < 0 || mx > 255 || mn > mx) {
    ctx.Fail(cap, "<Capability> range " + std::string(lo.value()) + ".." + hi.value() + " is not within 0..255, Min <= Max");
    return false;
  }
  *out = DmxRange{static_cast<uint8_t>(mn), static_cast<uint8_t>(mx)};
  return true;
}

void ReadWheel(QxfContext& ctx, const pugi::xml_node& ch, DmxChannel* out) {
  for (const pugi::xml_node cap : ch.children("Capability")) {
    WheelSlot slot;
    if (!CapabilityRange(ctx, cap, &slot.range)) return;
    if (CapabilityColor(cap, &slot.color)) {
      out->slots.push_back(slot);
    } else {
      const std::string text = Lower(cap.child_value());
      if (Contains(text, "open") || Contains(text, "white")) out->slots.push_back(WheelSlot{slot.range, Rgb8{}});
      // Others (rotation, random, split without colour): rendered as open.
    }
  }
}

void ReadShutter(QxfContext& ctx, const pugi::xml_node& ch, DmxChannel* out) {
  for (const pugi::xml_node cap : ch.children("Capability")) {
    DmxRange r;
    if (!CapabilityRange(ctx, cap, &r)) return;
    const std::string preset = cap.attribute("Preset").value();
    const std::string text = Lower(cap.child_value());
    const bool closed = preset == "ShutterClose" ||
                        (preset.empty() && (Contains(text, "close") || Contains(text, "blackout")));
    if (closed) out->closed.push_back(r);
  }
}

bool HasColoredCapability(const pugi::xml_node& ch) {
  Rgb8 c;
  for (const pugi::xml_node cap : ch.children("Capability")) {
    if (CapabilityColor(cap, &c)) return true;
  }
  return false;
}

// Channel presets (QLC+ 4.12+).
bool FromPreset(const std::string& p, const pugi::xml_node& ch, DmxChannel* c) {
  struct Entry {
    const char* preset;
    DmxFunction f;
  };
  static constexpr Entry kTable[] = {
      {"IntensityDimmer", DmxFunction::kDimmer},          {"IntensityMasterDimmer", DmxFunction::kDimmer},
      {"IntensityDimmerFine", DmxFunction::kDimmerFine},  {"IntensityMasterDimmerFine", DmxFunction::kDimmerFine},
      {"PositionPan", DmxFunction::kPan},                 {"PositionPanFine", DmxFunction::kPanFine},
      {"PositionTilt", DmxFunction::kTilt},               {"PositionTiltFine", DmxFunction::kTiltFine},
      {"IntensityRed", DmxFunction::kRed},                {"IntensityGreen", DmxFunction::kGreen},
      {"IntensityBlue", DmxFunction::kBlue},              {"IntensityWhite", DmxFunction::kWhite},
      {"IntensityCyan", DmxFunction::kCyan},              {"IntensityMagenta", DmxFunction::kMagenta},
      {"IntensityYellow", DmxFunction::kYellow},          {"BeamZoomSmallBig", DmxFunction::kZoom},
      {"BeamZoomBigSmall", DmxFunction::kZoom},           {"ShutterStrobeSlowFast", DmxFunction::kShutter},
      {"ShutterStrobeFastSlow", DmxFunction::kShutter},   {"ColorWheel", DmxFunction::kColorWheel},
      {"ColorMacro", DmxFunction::kColorWheel},
  };
  for (const Entry& e : kTable) {
    if (p == e.preset) {
      c->function = e.f;
      c->zoom_big_to_small = p == "BeamZoomBigSmall";
      if (e.f == DmxFunction::kColorWheel && !HasColoredCapability(ch)) {
        c->function = DmxFunction::kIgnored;
        c->ignored_why = "preset " + p + " without colours";
      }
      return true;
    }
  }
  c->ignored_why = "preset " + p;
  return false;
}

// Older style: <Group Byte="0|1">...</Group>, <Colour>...</Colour>.
void FromGroup(const pugi::xml_node& ch, DmxChannel* c) {
  const pugi::xml_node group = ch.child("Group");
  const std::string g = group.child_value();
  const bool fine = group.attribute("Byte").as_int(0) == 1;
  const std::string colour = ch.child_value("Colour");
  const std::string name = Lower(c->name);
  c->ignored_why = "group " + (g.empty() ? std::string("(none)") : g) + (fine ? " fine" : "");
  if (g == "Intensity") {
    struct Entry {
      const char* colour;
      DmxFunction f;
    };
    static constexpr Entry kColours[] = {
        {"Red", DmxFunction::kRed},     {"Green", DmxFunction::kGreen},     {"Blue", DmxFunction::kBlue},
        {"White", DmxFunction::kWhite}, {"Cyan", DmxFunction::kCyan},       {"Magenta", DmxFunction::kMagenta},
        {"Yellow", DmxFunction::kYellow},
    };
    if (colour.empty() || colour == "Generic") {
      c->function = fine ? DmxFunction::kDimmerFine : DmxFunction::kDimmer;
      return;
    }
    for (const Entry& e : kColours) {
      if (colour == e.colour && !fine) c->function = e.f;
    }
    if (c->function == DmxFunction::kIgnored) c->ignored_why = "intensity " + colour + (fine ? " fine" : "");
  } else if (g == "Pan") {
    c->function = fine ? DmxFunction::kPanFine : DmxFunction::kPan;
  } else if (g == "Tilt") {
    c->function = fine ? DmxFunction::kTiltFine : DmxFunction::kTilt;
  } else if (g == "Colour" && !fine && HasColoredCapability(ch)) {
    c->function = DmxFunction::kColorWheel;
  } else if (g == "Shutter" && !fine) {
    c->function = DmxFunction::kShutter;
  } else if (g == "Beam" && !fine && Contains(name, "zoom") && !Contains(name, "fine")) {
    c->function = DmxFunction::kZoom;
  }
}

int32_t DegreesQ16(const pugi::xml_attribute& a) {
  const double v = a.as_double(0.0);
  if (!(v > 0.0) || v > 3600.0) return 0;
  return static_cast<int32_t>(std::lround(v * 65536.0));
}

void ReadPhysical(const pugi::xml_node& phys, int* pan, int* tilt, int32_t* beam_min, int32_t* beam_max) {
  if (!phys) return;
  const pugi::xml_node focus = phys.child("Focus");
  if (focus) {
    *pan = std::clamp(focus.attribute("PanMax").as_int(0), 0, 3600);
    *tilt = std::clamp(focus.attribute("TiltMax").as_int(0), 0, 3600);
  }
  const pugi::xml_node lens = phys.child("Lens");
  if (lens) {
    *beam_min = DegreesQ16(lens.attribute("DegreesMin"));
    *beam_max = DegreesQ16(lens.attribute("DegreesMax"));
    if (*beam_max < *beam_min) std::swap(*beam_min, *beam_max);
  }
}

}  // namespace

Status ParseQxf(const std::string& text, const std::string& where, FixtureType* out) {
  *out = FixtureType{};
  out->where = where;
  pugi::xml_document doc;
  const pugi::xml_parse_result parsed = doc.load_buffer(text.data(), text.size());
  QxfContext ctx{text, where, {}};
  if (!parsed) {
    return Status(StatusCode::kInvalidArgument,
                  where + ":" + std::to_string(ctx.LineAt(parsed.offset)) + ": XML: " + parsed.description());
  }
  const pugi::xml_node root = doc.child("FixtureDefinition");
  if (!root) return Status(StatusCode::kInvalidArgument, where + ":1: not a QLC+ fixture (no <FixtureDefinition>)");
  out->manufacturer = root.child_value("Manufacturer");
  out->model = root.child_value("Model");
  out->type = root.child_value("Type");
  if (out->manufacturer.empty() || out->model.empty()) {
    ctx.Fail(root, "<Manufacturer> and <Model> are required");
  }
  ReadPhysical(root.child("Physical"), &out->pan_range_deg, &out->tilt_range_deg, &out->beam_min_q16, &out->beam_max_q16);

  for (const pugi::xml_node ch : root.children("Channel")) {
    DmxChannel c;
    c.name = ch.attribute("Name").value();
    c.line = ctx.Line(ch);
    if (c.name.empty()) ctx.Fail(ch, "<Channel> without a Name");
    for (const DmxChannel& other : out->channels) {
      if (other.name == c.name) ctx.Fail(ch, "channel '" + c.name + "' defined twice");
    }
    const std::string preset = ch.attribute("Preset").value();
    if (!preset.empty()) {
      FromPreset(preset, ch, &c);
    } else {
      FromGroup(ch, &c);
    }
    if (c.function == DmxFunction::kColorWheel) ReadWheel(ctx, ch, &c);
    if (c.function == DmxFunction::kShutter) ReadShutter(ctx, ch, &c);
    if (c.function == DmxFunction::kIgnored) {
      for (const pugi::xml_node cap : ch.children("Capability")) {
        DmxRange r;
        if (!CapabilityRange(ctx, cap, &r)) break;
      }
    }
    out->channels.push_back(std::move(c));
  }

  for (const pugi::xml_node m : root.children("Mode")) {
    DmxMode mode;
    mode.name = m.attribute("Name").value();
    mode.line = ctx.Line(m);
    if (mode.name.empty()) ctx.Fail(m, "<Mode> without a Name");
    for (const DmxMode& other : out->modes) {
      if (other.name == mode.name) ctx.Fail(m, "mode '" + mode.name + "' defined twice");
    }
    for (const pugi::xml_node mc : m.children("Channel")) {
      const int number = mc.attribute("Number").as_int(-1);
      if (number != static_cast<int>(mode.channels.size())) {
        ctx.Fail(mc, "mode '" + mode.name + "': channel Number " + mc.attribute("Number").value() + ", expected " +
                         std::to_string(mode.channels.size()));
      }
      const std::string name = mc.child_value();
      int index = -1;
      for (size_t i = 0; i < out->channels.size(); ++i) {
        if (out->channels[i].name == name) index = static_cast<int>(i);
      }
      if (index < 0) ctx.Fail(mc, "mode '" + mode.name + "' names unknown channel '" + name + "'");
      mode.channels.push_back(index);
    }
    if (mode.channels.empty()) ctx.Fail(m, "mode '" + mode.name + "' has no channels");
    if (mode.channels.size() > 512) ctx.Fail(m, "mode '" + mode.name + "' has more than 512 channels");
    ReadPhysical(m.child("Physical"), &mode.pan_range_deg, &mode.tilt_range_deg, &mode.beam_min_q16, &mode.beam_max_q16);
    out->modes.push_back(std::move(mode));
  }
  if (out->modes.empty() && ctx.error.empty()) ctx.Fail(root, "no <Mode>");
  if (!ctx.error.empty()) return Status(StatusCode::kInvalidArgument, ctx.error);
  return Status::Ok();
}

Status LoadQxf(const std::string& path, FixtureType* out) {
  std::string text;
  RELIGHT_RETURN_IF_ERROR(ReadTypeFile(path, &text));
  return ParseQxf(text, path, out);
}

}  // namespace relight::hal
