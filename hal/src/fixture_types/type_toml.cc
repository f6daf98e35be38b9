// The TOML form of a fixture type, for one QLC+'s library lacks:
//
//   manufacturer = "relight"
//   model = "Test Spot"
//   type = "Moving Head"
//   pan_range_deg = 540
//   tilt_range_deg = 270
//   beam_deg = [10.0, 40.0]            # narrowest, widest
//
//   [[channel]]
//   name = "Zoom"
//   function = "zoom"                  # DmxFunctionName() values; "ignored" for the rest
//   big_to_small = false               # zoom: 0 = widest
//   [[channel]]
//   name = "Colour"
//   function = "color_wheel"
//   slots = [ { min = 0, max = 15, color = "#ffffff" }, ... ]
//   [[channel]]
//   name = "Shutter"
//   function = "shutter"
//   closed = [[0, 7]]                  # DMX ranges that close it
//
//   [[mode]]
//   name = "16 bit"
//   pan_range_deg = 630                # optional: the mode's own <Physical>,
//   tilt_range_deg = 265               #   overriding the type's
//   beam_deg = [12.0, 30.0]
//   channels = ["Dimmer", "Pan", "Pan fine", ...]
//
// FixtureTypeToToml() (type_toml_write.cc) writes this form.
#include <toml++/toml.h>

#include <cmath>

#include "fixture_types/type_common.h"
#include "relight/hal/dmx/fixture_type.h"

namespace relight::hal {
namespace {

struct TypeError {
  std::string message;
};

class Reader {
 public:
  explicit Reader(const std::string& where) : where_(where) {}

  [[noreturn]] void Fail(const toml::node& node, const std::string& why) const {
    throw TypeError{where_ + ":" + std::to_string(node.source().begin.line) + ": " + why};
  }

  std::string Str(const toml::table& t, const char* key, bool required) const {
    const toml::node* n = t.get(key);
    if (n == nullptr) {
      if (required) Fail(t, std::string("missing '") + key + "'");
      return {};
    }
    if (!n->is_string()) Fail(*n, std::string("'") + key + "' must be a string");
    return *n->value<std::string>();
  }

  int64_t Int(const toml::node& n, const char* what, int64_t lo, int64_t hi) const {
    if (!n.is_integer()) Fail(n, std::string(what) + " must be an integer");
    const int64_t v = *n.value<int64_t>();
    if (v < lo || v > hi) {
      Fail(n, std::string(what) + " must be in " + std::to_string(lo) + ".." + std::to_string(hi));
    }
    return v;
  }

  int32_t DegreesQ16(const toml::node& n, const char* what) const {
    if (!n.is_number()) Fail(n, std::string(what) + " must be a number of degrees");
    const double v = *n.value<double>();
    if (!(v >= 0.0 && v <= 3600.0)) Fail(n, std::string(what) + " must be in 0..3600 degrees");
    return static_cast<int32_t>(std::lround(v * 65536.0));
  }

  DmxRange Range(const toml::node& lo, const toml::node& hi) const {
    const auto a = Int(lo, "min", 0, 255), b = Int(hi, "max", 0, 255);
    if (a > b) Fail(lo, "min must not exceed max");
    return DmxRange{static_cast<uint8_t>(a), static_cast<uint8_t>(b)};
  }

  void Channel(const toml::table& t, FixtureType* out) const {
    for (const auto& [key, node] : t) {
      const std::string_view k = key.str();
      if (k != "name" && k != "function" && k != "slots" && k != "closed" && k != "big_to_small") {
        Fail(node, "channel: unknown key '" + std::string(k) + "'");
      }
    }
    DmxChannel c;
    c.name = Str(t, "name", true);
    c.line = static_cast<int>(t.source().begin.line);
    const std::string fn = Str(t, "function", true);
    bool known = false;
    for (int i = 0; i < static_cast<int>(DmxFunction::kCount); ++i) {
      if (fn == DmxFunctionName(static_cast<DmxFunction>(i))) {
        c.function = static_cast<DmxFunction>(i);
        known = true;
      }
    }
    if (!known) Fail(*t.get("function"), "unknown function '" + fn + "'");
    if (c.function == DmxFunction::kIgnored) c.ignored_why = kTomlIgnoredWhy;
    for (const DmxChannel& other : out->channels) {
      if (other.name == c.name) Fail(t, "channel '" + c.name + "' defined twice");
    }
    if (const toml::node* b = t.get("big_to_small")) {
      if (!b->is_boolean()) Fail(*b, "'big_to_small' must be true or false");
      c.zoom_big_to_small = *b->value<bool>();
    }
    if (const toml::node* s = t.get("slots")) {
      if (c.function != DmxFunction::kColorWheel || !s->is_array()) Fail(*s, "'slots' is an array, for a color_wheel");
      for (const toml::node& e : *s->as_array()) {
        const toml::table* st = e.as_table();
        if (st == nullptr || !st->contains("min") || !st->contains("max") || !st->contains("color")) {
          Fail(e, "a slot is { min = .., max = .., color = \"#rrggbb\" }");
        }
        WheelSlot slot;
        slot.range = Range(*st->get("min"), *st->get("max"));
        const std::string color = Str(*st, "color", true);
        unsigned v = 0;
        if (color.size() != 7 || color[0] != '#' || std::sscanf(color.c_str() + 1, "%6x", &v) != 1) {
          Fail(*st->get("color"), "color must be \"#rrggbb\"");
        }
        slot.color = Rgb8{static_cast<uint8_t>(v >> 16), static_cast<uint8_t>(v >> 8), static_cast<uint8_t>(v)};
        c.slots.push_back(slot);
      }
    }
    if (const toml::node* s = t.get("closed")) {
      if (c.function != DmxFunction::kShutter || !s->is_array()) Fail(*s, "'closed' is an array, for a shutter");
      for (const toml::node& e : *s->as_array()) {
        const toml::array* pair = e.as_array();
        if (pair == nullptr || pair->size() != 2) Fail(e, "a closed range is [min, max]");
        c.closed.push_back(Range(*pair->get(0), *pair->get(1)));
      }
    }
    out->channels.push_back(std::move(c));
  }

  // pan_range_deg, tilt_range_deg, beam_deg: of the type or of one mode.
  void Physical(const toml::table& t, int* pan, int* tilt, int32_t* beam_min, int32_t* beam_max) const {
    if (const toml::node* n = t.get("pan_range_deg")) *pan = static_cast<int>(Int(*n, "pan_range_deg", 0, 3600));
    if (const toml::node* n = t.get("tilt_range_deg")) *tilt = static_cast<int>(Int(*n, "tilt_range_deg", 0, 3600));
    if (const toml::node* n = t.get("beam_deg")) {
      const toml::array* a = n->as_array();
      if (a == nullptr || a->size() != 2) Fail(*n, "beam_deg is [narrowest, widest]");
      *beam_min = DegreesQ16(*a->get(0), "beam_deg");
      *beam_max = DegreesQ16(*a->get(1), "beam_deg");
      if (*beam_min > *beam_max) Fail(*n, "beam_deg is [narrowest, widest]");
    }
  }

  void Mode(const toml::table& t, FixtureType* out) const {
    for (const auto& [key, node] : t) {
      const std::string_view k = key.str();
      if (k != "name" && k != "channels" && k != "pan_range_deg" && k != "tilt_range_deg" && k != "beam_deg") {
        Fail(node, "mode: unknown key '" + std::string(k) + "'");
      }
    }
    DmxMode m;
    m.name = Str(t, "name", true);
    m.line = static_cast<int>(t.source().begin.line);
    if (out->FindMode(m.name) != nullptr) Fail(t, "mode '" + m.name + "' defined twice");
    Physical(t, &m.pan_range_deg, &m.tilt_range_deg, &m.beam_min_q16, &m.beam_max_q16);
    const toml::node* list = t.get("channels");
    if (list == nullptr || !list->is_array() || list->as_array()->empty()) {
      Fail(t, "mode '" + m.name + "': 'channels' must be a non-empty array of channel names");
    }
    for (const toml::node& e : *list->as_array()) {
      if (!e.is_string()) Fail(e, "channel names are strings");
      const std::string name = *e.value<std::string>();
      int index = -1;
      for (size_t i = 0; i < out->channels.size(); ++i) {
        if (out->channels[i].name == name) index = static_cast<int>(i);
      }
      if (index < 0) Fail(e, "mode '" + m.name + "' names unknown channel '" + name + "'");
      m.channels.push_back(index);
    }
    if (m.channels.size() > 512) Fail(t, "mode '" + m.name + "' has more than 512 channels");
    out->modes.push_back(std::move(m));
  }

  void Type(const toml::table& root, FixtureType* out) const {
    for (const auto& [key, node] : root) {
      const std::string_view k = key.str();
      if (k != "manufacturer" && k != "model" && k != "type" && k != "pan_range_deg" && k != "tilt_range_deg" &&
          k != "beam_deg" && k != "channel" && k != "mode") {
        Fail(node, "unknown key '" + std::string(k) + "'");
      }
    }
    out->manufacturer = Str(root, "manufacturer", true);
    out->model = Str(root, "model", true);
    out->type = Str(root, "type", false);
    Physical(root, &out->pan_range_deg, &out->tilt_range_deg, &out->beam_min_q16, &out->beam_max_q16);
    const toml::array* channels = root["channel"].as_array();
    const toml::array* modes = root["mode"].as_array();
    if (channels == nullptr) Fail(root, "no [[channel]]");
    for (const toml::node& c : *channels) {
      if (!c.is_table()) Fail(c, "[[channel]] entries are tables");
      Channel(*c.as_table(), out);
    }
    if (modes == nullptr) Fail(root, "no [[mode]]");
    for (const toml::node& m : *modes) {
      if (!m.is_table()) Fail(m, "[[mode]] entries are tables");
      Mode(*m.as_table(), out);
    }
  }

 private:
  const std::string& where_;
};

}  // namespace

Status ParseFixtureTypeToml(const std::string& text, const std::string& where, FixtureType* out) {
  *out = FixtureType{};
  out->where = where;
  try {
    const toml::table root = toml::parse(text, where);
    Reader(where).Type(root, out);
  } catch (const toml::parse_error& e) {
    return Status(StatusCode::kInvalidArgument,
                  where + ":" + std::to_string(e.source().begin.line) + ": " + std::string(e.description()));
  } catch (const TypeError& e) {
    return Status(StatusCode::kInvalidArgument, e.message);
  }
  return Status::Ok();
}

Status LoadFixtureTypeToml(const std::string& path, FixtureType* out) {
  std::string text;
  RELIGHT_RETURN_IF_ERROR(ReadTypeFile(path, &text));
  return ParseFixtureTypeToml(text, path, out);
}

}  // namespace relight::hal
