#include "gpio_decoder.h"


namespace relight::hal {
namespace {

// Direction of a move from state `from` to `to` (A << 1 | B), forward being
// 00 -> 01 -> 11 -> 10 -> 00; 0 for no move or an impossible two-bit jump.
int QuadratureStep(int from, int to) {
  static constexpr int8_t kTable[16] = {
      // to:  00  01  10  11
      0, +1, -1, 0,   // from 00
      -1, 0, 0, +1,   // from 01
      +1, 0, 0, -1,   // from 10
      0, -1, +1, 0,   // from 11
  };
  return kTable[from * 4 + to];
}

// `value` in the parameter's format: Q16.16 degrees or a Q1.15 level.
ParamChange Change(int fixture, Param param, int32_t value, int64_t time_us) {
  const uint16_t index = static_cast<uint16_t>(fixture);
  return IsAngle(param) ? ParamChange::Angle(time_us, index, param, Q16_16::FromRaw(value))
                        : ParamChange::Level(time_us, index, param, Q1_15::FromRaw(static_cast<int16_t>(value)));
}

int IndexOf(const Patch& patch, const std::string& name) {
  for (size_t i = 0; i < patch.fixtures.size() && i <= static_cast<size_t>(kMaxFixtures); ++i) {
    if (patch.fixtures[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace

GpioDecoder::GpioDecoder(const Patch& patch) {
  const std::vector<GpioButtonConfig>& buttons = patch.buttons;
  const std::vector<GpioEncoderConfig>& encoders = patch.encoders;
  for (size_t i = 0; i < buttons.size(); ++i) {
    Button b;
    b.config = buttons[i];
    b.fixture = IndexOf(patch, b.config.fixture);
    for (const NamedChange& c : b.config.preset) {
      const int index = IndexOf(patch, c.fixture);
      if (index < 0) continue;
      b.preset.push_back(c.change);
      b.preset.back().fixture = static_cast<uint16_t>(index);
    }
    b.raw = b.stable = b.config.active_low;  // released
    buttons_.push_back(b);
    lines_.push_back({buttons[i].chip, buttons[i].line, "gpio_button " + std::to_string(i + 1)});
  }
  for (size_t i = 0; i < encoders.size(); ++i) {
    Encoder e;
    e.config = encoders[i];
    e.fixture = IndexOf(patch, e.config.fixture);
    e.value = encoders[i].start;
    encoders_.push_back(e);
    lines_.push_back({encoders[i].chip, encoders[i].line_a, "gpio_encoder " + std::to_string(i + 1) + " A"});
    lines_.push_back({encoders[i].chip, encoders[i].line_b, "gpio_encoder " + std::to_string(i + 1) + " B"});
  }
}

int GpioDecoder::Find(const std::string& chip, int line) const {
  for (size_t i = 0; i < lines_.size(); ++i) {
    if (lines_[i].chip == chip && lines_[i].line == line) return static_cast<int>(i);
  }
  return -1;
}

void GpioDecoder::SetInitial(int index, bool level) {
  const size_t i = static_cast<size_t>(index);
  if (i < buttons_.size()) {
    buttons_[i].raw = buttons_[i].stable = level;
    return;
  }
  Encoder& e = encoders_[(i - buttons_.size()) / 2];
  const int bit = (i - buttons_.size()) % 2 == 0 ? 2 : 1;
  e.state = level ? (e.state | bit) : (e.state & ~bit);
}

void GpioDecoder::Settle(Button& b, int64_t now_us, ChangeRing* out) {
  if (b.raw == b.stable || now_us - b.changed_us < int64_t{b.config.debounce_ms} * 1000) return;
  b.stable = b.raw;
  const bool pressed = b.stable != b.config.active_low;
  if (!pressed) return;
  const int64_t at_us = b.changed_us + int64_t{b.config.debounce_ms} * 1000;
  if (b.config.action == ButtonAction::kToggle) {
    b.on = !b.on;
    if (b.fixture >= 0) out->Push(Change(b.fixture, Param::kDimmer, b.on ? b.config.on_level_q15 : 0, at_us));
  } else {
    for (ParamChange c : b.preset) {
      c.time_us = at_us;
      out->Push(c);
    }
  }
}

void GpioDecoder::Step(Encoder& e, int new_state, int64_t time_us, ChangeRing* out) {
  const int dir = QuadratureStep(e.state, new_state);
  e.state = new_state;
  if (dir == 0) return;
  const bool angle = IsAngle(e.config.param);
  const bool zoom = e.config.param == Param::kZoom;  // a beam angle, in (0, 180); the engine clamps to the bake's range
  const int64_t lo = zoom ? 655 : angle ? -720 * 65536 : 0;
  const int64_t hi = zoom ? 180 * 65536 - 655 : angle ? 720 * 65536 : 32767;
  int64_t v = int64_t{e.value} + dir * int64_t{e.config.step};
  v = v < lo ? lo : v > hi ? hi : v;
  if (v == e.value) return;
  e.value = static_cast<int32_t>(v);
  if (e.fixture >= 0) out->Push(Change(e.fixture, e.config.param, e.value, time_us));
}

void GpioDecoder::OnEdge(int index, bool level, int64_t time_us, ChangeRing* out) {
  const size_t i = static_cast<size_t>(index);
  if (i < buttons_.size()) {
    Button& b = buttons_[i];
    Settle(b, time_us, out);
    if (level != b.raw) {
      b.raw = level;
      b.changed_us = time_us;
    }
    return;
  }
  Encoder& e = encoders_[(i - buttons_.size()) / 2];
  const int bit = (i - buttons_.size()) % 2 == 0 ? 2 : 1;
  Step(e, level ? (e.state | bit) : (e.state & ~bit), time_us, out);
}

void GpioDecoder::Tick(int64_t now_us, ChangeRing* out) {
  for (Button& b : buttons_) Settle(b, now_us, out);
}

}  // namespace relight::hal
