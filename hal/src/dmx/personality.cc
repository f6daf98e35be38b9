// FixtureType + mode -> DmxPersonality (offsets and lookup tables).
#include "relight/hal/dmx/personality.h"

namespace relight::hal {

Status BuildPersonality(const FixtureType& type, const std::string& mode_name, DmxPersonality* out) {
  const DmxMode* mode = type.FindMode(mode_name);
  if (mode == nullptr) {
    std::string known;
    for (const DmxMode& m : type.modes) known += (known.empty() ? "'" : ", '") + m.name + "'";
    return Status(StatusCode::kNotFound,
                  type.where + ": " + type.manufacturer + " " + type.model + " has no mode '" + mode_name +
                      "' (modes: " + known + ")");
  }
  *out = DmxPersonality{};
  out->offset.fill(-1);
  out->footprint = static_cast<uint16_t>(mode->channels.size());
  for (size_t i = 0; i < mode->channels.size(); ++i) {
    const DmxChannel& c = type.channels[static_cast<size_t>(mode->channels[i])];
    int16_t& slot = out->offset[static_cast<size_t>(c.function)];
    if (c.function == DmxFunction::kIgnored || slot >= 0) continue;
    slot = static_cast<int16_t>(i);
    if (c.function == DmxFunction::kColorWheel) {
      out->has_wheel = true;
      for (auto& rgb : out->wheel) rgb = {255, 255, 255};  // between slots: open
      for (const WheelSlot& s : c.slots) {
        for (int v = s.range.min; v <= s.range.max; ++v) {
          out->wheel[static_cast<size_t>(v)] = {s.color.r, s.color.g, s.color.b};
        }
      }
    }
    if (c.function == DmxFunction::kShutter) {
      out->has_shutter_ranges = true;
      out->shutter_open.fill(1);
      for (const DmxRange& r : c.closed) {
        for (int v = r.min; v <= r.max; ++v) out->shutter_open[static_cast<size_t>(v)] = 0;
      }
    }
    if (c.function == DmxFunction::kZoom) out->zoom_big_to_small = c.zoom_big_to_small;
  }
  const bool mode_beam = mode->beam_max_q16 > 0;
  out->beam_min_q16 = mode_beam ? mode->beam_min_q16 : type.beam_min_q16;
  out->beam_max_q16 = mode_beam ? mode->beam_max_q16 : type.beam_max_q16;
  out->pan_range_deg = mode->pan_range_deg > 0 ? mode->pan_range_deg : type.pan_range_deg;
  out->tilt_range_deg = mode->tilt_range_deg > 0 ? mode->tilt_range_deg : type.tilt_range_deg;
  return Status::Ok();
}

}  // namespace relight::hal
