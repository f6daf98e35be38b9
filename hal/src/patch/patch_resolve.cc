// Completes a patch against the bake's luminaires: defaults for fixtures the
// patch does not name, the luminaires' console ranges where the patch gives
// none, a register block for each, names checked.
#include <algorithm>

#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace relight::hal {
namespace {

std::string Where(const Patch& patch, int line) {
  return (patch.where.empty() ? std::string("patch") : patch.where) + (line > 0 ? ":" + std::to_string(line) : "");
}

const LuminaireConsole* Find(const std::vector<LuminaireConsole>& luminaires, const std::string& name) {
  for (const LuminaireConsole& l : luminaires) {
    if (l.name == name) return &l;
  }
  return nullptr;
}

bool IsEmitter(const Patch& patch, const std::string& name) {
  for (const EmitterPatch& e : patch.emitters) {
    if (e.control.name == name) return true;
  }
  return false;
}

// Inputs may drive a luminaire or an emitter.
Status CheckFixture(const Patch& patch, const std::vector<LuminaireConsole>& luminaires, const std::string& fixture,
                    int line, const char* what) {
  if (Find(luminaires, fixture) != nullptr || IsEmitter(patch, fixture)) return Status::Ok();
  std::string list;
  for (const LuminaireConsole& l : luminaires) list += (list.empty() ? "" : ", ") + l.name;
  for (const EmitterPatch& e : patch.emitters) list += (list.empty() ? "" : ", ") + e.control.name + " (emitter)";
  return Status(StatusCode::kNotFound,
                Where(patch, line) + ": " + what + ": no luminaire or emitter '" + fixture + "' (the bake has: " +
                    list + ")");
}

std::string Span(const FixturePatch& f) {
  return std::to_string(f.modbus_base) + ".." + std::to_string(f.modbus_base + f.layout.size() - 1);
}

}  // namespace

Status ResolvePatch(const std::vector<LuminaireConsole>& luminaires, Patch* patch) {
  for (const FixturePatch& f : patch->fixtures) {
    if (f.emitter >= 0) {
      return Status(StatusCode::kInvalidArgument, Where(*patch, f.line) + ": patch resolved twice");
    }
    if (Find(luminaires, f.name) != nullptr) continue;
    std::string list;
    for (const LuminaireConsole& l : luminaires) list += (list.empty() ? "" : ", ") + l.name;
    return Status(StatusCode::kNotFound, Where(*patch, f.line) + ": fixture: no luminaire '" + f.name +
                                             "' in the bake (it has: " + list + ")");
  }
  for (const EmitterPatch& e : patch->emitters) {
    if (Find(luminaires, e.control.name) != nullptr) {
      return Status(StatusCode::kInvalidArgument, Where(*patch, e.control.line) + ": emitter '" + e.control.name +
                                                      "': the bake has a luminaire of that name; name it otherwise");
    }
  }
  for (const LuminaireConsole& l : luminaires) {
    const bool listed = std::any_of(patch->fixtures.begin(), patch->fixtures.end(),
                                    [&](const FixturePatch& f) { return f.name == l.name; });
    if (!listed) {
      FixturePatch f;
      f.name = l.name;
      patch->fixtures.push_back(f);
    }
  }
  for (FixturePatch& f : patch->fixtures) {
    const LuminaireConsole* l = Find(luminaires, f.name);
    if (f.pan_range_q16 <= 0) f.pan_range_q16 = l->pan_range_q16;
    if (f.tilt_range_q16 <= 0) f.tilt_range_q16 = l->tilt_range_q16;
  }
  // Emitters after the luminaires: inputs address them as fixtures.
  for (const EmitterPatch& e : patch->emitters) {
    patch->fixtures.push_back(e.control);
    patch->fixtures.back().pan_range_q16 = 540 << 16;  // unused (an emitter has no pan or tilt), but valid
    patch->fixtures.back().tilt_range_q16 = 270 << 16;
  }
  // Explicit blocks first, then the rest in order after the highest one.
  int next = 0;
  for (const FixturePatch& f : patch->fixtures) {
    if (f.modbus_base >= 0) next = std::max(next, f.modbus_base + f.layout.size());
  }
  for (FixturePatch& f : patch->fixtures) {
    if (f.modbus_base >= 0) continue;
    if (next + f.layout.size() > 65536) {
      return Status(StatusCode::kInvalidArgument, Where(*patch, f.line) + ": fixture '" + f.name +
                                                      "': no room for its registers below 65536");
    }
    f.modbus_base = next;
    next += f.layout.size();
  }
  for (size_t i = 0; i < patch->fixtures.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      const FixturePatch& a = patch->fixtures[j];
      const FixturePatch& b = patch->fixtures[i];
      if (a.modbus_base < b.modbus_base + b.layout.size() && b.modbus_base < a.modbus_base + a.layout.size()) {
        return Status(StatusCode::kInvalidArgument, Where(*patch, b.line) + ": fixture '" + b.name + "': registers " +
                                                        Span(b) + " overlap fixture '" + a.name + "' at " + Span(a));
      }
    }
  }
  for (const GpioButtonConfig& b : patch->buttons) {
    if (b.action == ButtonAction::kToggle) {
      RELIGHT_RETURN_IF_ERROR(CheckFixture(*patch, luminaires, b.fixture, b.config_line, "gpio_button"));
    }
    for (const NamedChange& c : b.preset) {
      RELIGHT_RETURN_IF_ERROR(CheckFixture(*patch, luminaires, c.fixture, b.config_line, "gpio_button preset"));
    }
  }
  for (const GpioEncoderConfig& e : patch->encoders) {
    RELIGHT_RETURN_IF_ERROR(CheckFixture(*patch, luminaires, e.fixture, e.config_line, "gpio_encoder"));
  }
  for (const PollEntry& e : patch->modbus_poller.map) {
    RELIGHT_RETURN_IF_ERROR(CheckFixture(*patch, luminaires, e.fixture, e.line, "[modbus_poller] map"));
    const auto f = std::find_if(patch->fixtures.begin(), patch->fixtures.end(),
                                [&](const FixturePatch& p) { return p.name == e.fixture; });
    if (!f->layout.Has(e.channel)) {
      return Status(StatusCode::kInvalidArgument, Where(*patch, e.line) + ": [modbus_poller] map: fixture '" +
                                                      e.fixture + "' has no '" + ChannelName(e.channel) +
                                                      "' register in its layout");
    }
  }
  return Status::Ok();
}

}  // namespace relight::hal
