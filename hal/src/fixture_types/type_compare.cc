// Two fixture types compared on what they mean to a renderer and a patch:
// the first difference as text. What says where a type came from (line,
// where, ignored_why) is left out. Used to check a written TOML form reads
// back as the type it was written from (relight-fixture-type, the tests).
#include <string>

#include "relight/hal/dmx/fixture_type.h"

namespace relight::hal {
namespace {

std::string Quote(const std::string& s) { return "'" + s + "'"; }

std::string RangeText(const DmxRange& r) { return std::to_string(r.min) + ".." + std::to_string(r.max); }

std::string ColorText(const Rgb8& c) {
  return "rgb(" + std::to_string(c.r) + "," + std::to_string(c.g) + "," + std::to_string(c.b) + ")";
}

// A mode's channel index as the channel's name.
std::string ChannelAt(const FixtureType& t, int index) {
  if (index < 0 || static_cast<size_t>(index) >= t.channels.size()) return "#" + std::to_string(index);
  return "#" + std::to_string(index) + " " + Quote(t.channels[static_cast<size_t>(index)].name);
}

std::string Mismatch(const std::string& what, const std::string& a, const std::string& b) {
  return what + ": " + a + " vs " + b;
}

// The <Physical> fields the type and each mode carry.
std::string PhysicalDifference(const std::string& what, int pan_a, int pan_b, int tilt_a, int tilt_b,
                               int32_t min_a, int32_t min_b, int32_t max_a, int32_t max_b) {
  if (pan_a != pan_b) return Mismatch(what + "pan_range_deg", std::to_string(pan_a), std::to_string(pan_b));
  if (tilt_a != tilt_b) return Mismatch(what + "tilt_range_deg", std::to_string(tilt_a), std::to_string(tilt_b));
  if (min_a != min_b) return Mismatch(what + "beam_min_q16", std::to_string(min_a), std::to_string(min_b));
  if (max_a != max_b) return Mismatch(what + "beam_max_q16", std::to_string(max_a), std::to_string(max_b));
  return {};
}

std::string ChannelDifference(const std::string& what, const DmxChannel& a, const DmxChannel& b) {
  if (a.name != b.name) return Mismatch(what + "name", Quote(a.name), Quote(b.name));
  if (a.function != b.function) return Mismatch(what + "function", DmxFunctionName(a.function), DmxFunctionName(b.function));
  if (a.zoom_big_to_small != b.zoom_big_to_small) {
    return Mismatch(what + "big_to_small", a.zoom_big_to_small ? "true" : "false", b.zoom_big_to_small ? "true" : "false");
  }
  if (a.slots.size() != b.slots.size()) {
    return Mismatch(what + "slot count", std::to_string(a.slots.size()), std::to_string(b.slots.size()));
  }
  for (size_t i = 0; i < a.slots.size(); ++i) {
    const WheelSlot &sa = a.slots[i], &sb = b.slots[i];
    const std::string slot = what + "slot " + std::to_string(i) + " ";
    if (sa.range.min != sb.range.min || sa.range.max != sb.range.max) {
      return Mismatch(slot + "range", RangeText(sa.range), RangeText(sb.range));
    }
    if (sa.color.r != sb.color.r || sa.color.g != sb.color.g || sa.color.b != sb.color.b) {
      return Mismatch(slot + "color", ColorText(sa.color), ColorText(sb.color));
    }
  }
  if (a.closed.size() != b.closed.size()) {
    return Mismatch(what + "closed count", std::to_string(a.closed.size()), std::to_string(b.closed.size()));
  }
  for (size_t i = 0; i < a.closed.size(); ++i) {
    if (a.closed[i].min != b.closed[i].min || a.closed[i].max != b.closed[i].max) {
      return Mismatch(what + "closed " + std::to_string(i), RangeText(a.closed[i]), RangeText(b.closed[i]));
    }
  }
  return {};
}

}  // namespace

std::string FixtureTypeDifference(const FixtureType& a, const FixtureType& b) {
  if (a.manufacturer != b.manufacturer) return Mismatch("manufacturer", Quote(a.manufacturer), Quote(b.manufacturer));
  if (a.model != b.model) return Mismatch("model", Quote(a.model), Quote(b.model));
  if (a.type != b.type) return Mismatch("type", Quote(a.type), Quote(b.type));
  std::string d = PhysicalDifference("", a.pan_range_deg, b.pan_range_deg, a.tilt_range_deg, b.tilt_range_deg,
                                     a.beam_min_q16, b.beam_min_q16, a.beam_max_q16, b.beam_max_q16);
  if (!d.empty()) return d;
  if (a.channels.size() != b.channels.size()) {
    return Mismatch("channel count", std::to_string(a.channels.size()), std::to_string(b.channels.size()));
  }
  for (size_t i = 0; i < a.channels.size(); ++i) {
    d = ChannelDifference("channel " + std::to_string(i) + " " + Quote(a.channels[i].name) + ": ", a.channels[i],
                          b.channels[i]);
    if (!d.empty()) return d;
  }
  if (a.modes.size() != b.modes.size()) {
    return Mismatch("mode count", std::to_string(a.modes.size()), std::to_string(b.modes.size()));
  }
  for (size_t i = 0; i < a.modes.size(); ++i) {
    const DmxMode &ma = a.modes[i], &mb = b.modes[i];
    const std::string what = "mode " + std::to_string(i) + " " + Quote(ma.name) + ": ";
    if (ma.name != mb.name) return Mismatch(what + "name", Quote(ma.name), Quote(mb.name));
    d = PhysicalDifference(what, ma.pan_range_deg, mb.pan_range_deg, ma.tilt_range_deg, mb.tilt_range_deg,
                           ma.beam_min_q16, mb.beam_min_q16, ma.beam_max_q16, mb.beam_max_q16);
    if (!d.empty()) return d;
    if (ma.channels.size() != mb.channels.size()) {
      return Mismatch(what + "channel count", std::to_string(ma.channels.size()), std::to_string(mb.channels.size()));
    }
    for (size_t k = 0; k < ma.channels.size(); ++k) {
      if (ma.channels[k] != mb.channels[k]) {
        return Mismatch(what + "channel at offset " + std::to_string(k), ChannelAt(a, ma.channels[k]),
                        ChannelAt(b, mb.channels[k]));
      }
    }
  }
  return {};
}

}  // namespace relight::hal
