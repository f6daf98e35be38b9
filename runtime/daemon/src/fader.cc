#include "relight/control/fader.h"

namespace relight::control {

int32_t ApplyDimmerCurve(hal::DimmerCurve curve, int32_t level_q15) {
  const int32_t level = level_q15 < 0 ? 0 : level_q15 > 32767 ? 32767 : level_q15;
  switch (curve) {
    case hal::DimmerCurve::kLinear: return level;
    case hal::DimmerCurve::kSquare:  // out = in^2; the product < 2^30 fits int32
      return (level * level + 16383) / 32767;
  }
  return level;
}

Fader::Fader(const std::vector<hal::FixturePatch>& fixtures) : slots_(fixtures.size()) {
  // Slots are uint16_t indices (param.h kMaxFixtures); the patch and DMX readers keep below that.
  for (size_t i = 0; i < fixtures.size(); ++i) slots_[i].patch = fixtures[i];
}

void Fader::Reset(int slot, const FixtureState& state) {
  const int32_t values[kParamCount] = {state.pan_deg.raw(), state.tilt_deg.raw(), state.dimmer.raw(),
                                       state.rgb[0].raw(),  state.rgb[1].raw(),  state.rgb[2].raw(),
                                       state.roll_deg.raw(), state.zoom_deg.raw()};  // in Param order; x, y, size 0
  ResetValues(slot, values, /*emitter=*/false);
}

void Fader::ResetValues(int slot, const int32_t values[kParamCount], bool emitter) {
  Slot& s = slots_[static_cast<size_t>(slot)];
  for (int p = 0; p < kParamCount; ++p) {
    s.ramps[p] = Ramp();
    s.ramps[p].from = s.ramps[p].to = s.ramps[p].shown = values[p];
    // Report only what the slot has: a luminaire no x, an emitter no pan.
    s.ramps[p].report = emitter ? IsEmitterParam(static_cast<Param>(p)) : p < kFixtureParamCount;
  }
}

int32_t Fader::ValueAt(const Ramp& ramp, int64_t now_us) {
  const int64_t elapsed = now_us - ramp.start_us;
  if (ramp.duration_us <= 0 || elapsed >= ramp.duration_us) return ramp.to;
  if (elapsed <= 0) return ramp.from;
  // |to - from| < 2^32 and elapsed < 2^40 (fade_ms <= 600 s): the product fits int64.
  const int64_t delta = static_cast<int64_t>(ramp.to) - ramp.from;
  return static_cast<int32_t>(ramp.from + delta * elapsed / ramp.duration_us);
}

bool Fader::SetTarget(const ParamChange& change, int64_t now_us) {
  if (change.fixture >= slots_.size() || static_cast<int>(change.param) >= kParamCount) return false;
  Slot& s = slots_[change.fixture];
  Ramp& r = s.ramps[static_cast<int>(change.param)];
  r.from = ValueAt(r, now_us);
  r.to = IsAngle(change.param) ? change.degrees.raw() : change.level.raw();
  r.start_us = now_us;
  r.duration_us = int64_t{s.patch.fade_ms} * 1000;
  return true;
}

size_t Fader::Step(int64_t now_us, ParamChange* out) {
  size_t n = 0;
  for (size_t slot = 0; slot < slots_.size(); ++slot) {
    Slot& s = slots_[slot];
    for (int p = 0; p < kParamCount; ++p) {
      Ramp& r = s.ramps[p];
      const Param param = static_cast<Param>(p);
      int32_t value = ValueAt(r, now_us);
      if (param == Param::kDimmer) value = ApplyDimmerCurve(s.patch.dimmer_curve, value);
      if (value == r.shown && !r.report) continue;
      r.shown = value;
      r.report = false;
      // A ramp between two Q1.15 levels stays within int16.
      const uint16_t index = static_cast<uint16_t>(slot);
      out[n++] = IsAngle(param) ? ParamChange::Angle(now_us, index, param, Q16_16::FromRaw(value))
                                : ParamChange::Level(now_us, index, param, Q1_15::FromRaw(static_cast<int16_t>(value)));
    }
  }
  return n;
}

void Fader::CopyRampsFrom(const Fader& old) {
  for (Slot& s : slots_) {
    for (const Slot& o : old.slots_) {
      if (o.patch.name != s.patch.name) continue;
      for (int p = 0; p < kParamCount; ++p) {
        const bool reported = s.ramps[p].report;  // what the slot has (ResetValues)
        s.ramps[p] = o.ramps[p];
        s.ramps[p].report = reported;
      }
    }
  }
}

bool Fader::Idle(int64_t now_us) const {
  for (const Slot& s : slots_) {
    for (const Ramp& r : s.ramps) {
      if (r.duration_us > 0 && now_us - r.start_us < r.duration_us) return false;
    }
  }
  return true;
}

}  // namespace relight::control
