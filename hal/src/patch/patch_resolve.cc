// Completes a patch against the bake's luminaires: defaults for fixtures the
// patch does not name, a register block for each, names checked.
#include <algorithm>

#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace relight::hal {
namespace {

std::string Where(const Patch& patch, int line) {
  return (patch.where.empty() ? std::string("patch") : patch.where) + (line > 0 ? ":" + std::to_string(line) : "");
}

Status CheckFixture(const Patch& patch, const std::vector<std::string>& names, const std::string& fixture, int line,
                    const char* what) {
  if (std::find(names.begin(), names.end(), fixture) != names.end()) return Status::Ok();
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  return Status(StatusCode::kNotFound,
                Where(patch, line) + ": " + what + ": no luminaire '" + fixture + "' in the bake (it has: " + list + ")");
}

}  // namespace

Status ResolvePatch(const std::vector<std::string>& luminaire_names, Patch* patch) {
  for (const FixturePatch& f : patch->fixtures) {
    RELIGHT_RETURN_IF_ERROR(CheckFixture(*patch, luminaire_names, f.name, f.line, "fixture"));
  }
  for (const std::string& name : luminaire_names) {
    const bool listed = std::any_of(patch->fixtures.begin(), patch->fixtures.end(),
                                    [&](const FixturePatch& f) { return f.name == name; });
    if (!listed) {
      FixturePatch f;
      f.name = name;
      patch->fixtures.push_back(f);
    }
  }
  // Explicit blocks first, then the rest in order after the highest one.
  int next = 0;
  for (const FixturePatch& f : patch->fixtures) {
    if (f.modbus_base >= 0) next = std::max(next, f.modbus_base + kRegistersPerFixture);
  }
  for (FixturePatch& f : patch->fixtures) {
    if (f.modbus_base >= 0) continue;
    if (next + kRegistersPerFixture > 65536) {
      return Status(StatusCode::kInvalidArgument, Where(*patch, f.line) + ": fixture '" + f.name +
                                                      "': no room for its registers below 65536");
    }
    f.modbus_base = next;
    next += kRegistersPerFixture;
  }
  for (size_t i = 0; i < patch->fixtures.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      const FixturePatch& a = patch->fixtures[j];
      const FixturePatch& b = patch->fixtures[i];
      if (a.modbus_base < b.modbus_base + kRegistersPerFixture && b.modbus_base < a.modbus_base + kRegistersPerFixture) {
        return Status(StatusCode::kInvalidArgument,
                      Where(*patch, b.line) + ": fixture '" + b.name + "': registers " +
                          std::to_string(b.modbus_base) + ".." + std::to_string(b.modbus_base + 7) +
                          " overlap fixture '" + a.name + "' at " + std::to_string(a.modbus_base) + ".." +
                          std::to_string(a.modbus_base + 7));
      }
    }
  }
  for (const GpioButtonConfig& b : patch->buttons) {
    if (b.action == ButtonAction::kToggle) {
      RELIGHT_RETURN_IF_ERROR(CheckFixture(*patch, luminaire_names, b.fixture, b.config_line, "gpio_button"));
    }
    for (const ParamChange& c : b.preset) {
      RELIGHT_RETURN_IF_ERROR(CheckFixture(*patch, luminaire_names, c.fixture, b.config_line, "gpio_button preset"));
    }
  }
  for (const GpioEncoderConfig& e : patch->encoders) {
    RELIGHT_RETURN_IF_ERROR(CheckFixture(*patch, luminaire_names, e.fixture, e.config_line, "gpio_encoder"));
  }
  for (const PollEntry& e : patch->modbus_poller.map) {
    RELIGHT_RETURN_IF_ERROR(CheckFixture(*patch, luminaire_names, e.fixture, e.line, "[modbus_poller] map"));
  }
  return Status::Ok();
}

}  // namespace relight::hal
