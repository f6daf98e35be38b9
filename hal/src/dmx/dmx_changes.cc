#include "dmx_changes.h"

#include "relight/base/console_value.h"

namespace relight::hal {
namespace {

constexpr int kDefaultPanRangeDeg = 540;   // the usual moving-head ranges (PITFALLS.md)
constexpr int kDefaultTiltRangeDeg = 270;

// dimmer x scale / 2^15, scale in 0 .. 2^15 (exact at both ends).
Q1_15 ScaledDimmer(Q1_15 dimmer, int32_t scale_q15) {
  return Q1_15::FromRaw(static_cast<int16_t>((int32_t{dimmer.raw()} * scale_q15) >> 15));
}

}  // namespace

DmxChanges::DmxChanges(const DmxPatch& patch)
    : patch_(patch),
      fixtures_(patch.fixtures.size()),
      snapshot_(patch.fixtures.size()),
      pending_(patch.fixtures.size() * kParamCount) {}

void DmxChanges::OnFrame(unsigned universe, const uint8_t* slots, size_t count, int64_t arrival_us) {
  std::lock_guard<std::mutex> lock(mu_);
  for (size_t i = 0; i < fixtures_.size(); ++i) {
    const DmxFixturePatch& p = patch_.fixtures[i];
    if (static_cast<unsigned>(p.universe) != universe) continue;
    if (DecodeDmxFrame(p.personality, p.address, kDmxNullStartCode, slots, count, &fixtures_[i].values)) {
      fixtures_[i].last_frame_us = arrival_us;
      fixtures_[i].received = true;
    }
  }
}

bool DmxChanges::Lost(const Fixture& f, int64_t now_us) const {
  return f.received && now_us - f.last_frame_us > int64_t{patch_.loss_timeout_ms} * 1000;
}

int32_t DmxChanges::LossDimmerScaleQ15(const Fixture& f, int64_t now_us) const {
  constexpr int32_t kAll = 1 << 15;
  if (patch_.loss_policy == DmxLossPolicy::kHold || !Lost(f, now_us)) return kAll;
  if (patch_.loss_policy == DmxLossPolicy::kBlackout) return 0;
  // kFade: linear from the moment the signal counts as lost.
  const int64_t since_us = now_us - f.last_frame_us - int64_t{patch_.loss_timeout_ms} * 1000;
  const int64_t fade_us = int64_t{patch_.loss_fade_ms} * 1000;
  if (since_us >= fade_us) return 0;
  return static_cast<int32_t>(kAll - since_us * kAll / fade_us);
}

bool DmxChanges::LatestValues(size_t index, int64_t now_us, DmxFixtureValues* out) const {
  std::lock_guard<std::mutex> lock(mu_);
  if (index >= fixtures_.size()) return false;
  *out = fixtures_[index].values;
  // Loss of signal. Holding the last look is the default because relight is
  // a visualiser: a console rebooting or a network hiccup should not black
  // out the picture someone is programming against, and most real fixtures
  // hold their last DMX look too, so holding shows what the rig would do.
  // "fade" and "blackout" are for rooms where a lost console must mean dark:
  // a fade shows it going, as a console's own blackout would.
  out->dimmer = ScaledDimmer(out->dimmer, LossDimmerScaleQ15(fixtures_[index], now_us));
  return true;
}

size_t DmxChanges::Report(size_t index, int32_t dimmer_scale_q15, Fixture& shown, ParamChange* out) const {
  const DmxPersonality& p = patch_.fixtures[index].personality;
  const uint16_t fixture = static_cast<uint16_t>(index);
  const int64_t t = shown.last_frame_us;
  size_t n = 0;
  const auto level = [&](Param param, Q1_15 v) {
    int32_t& was = shown.shown[static_cast<int>(param)];
    if (shown.reported && was == v.raw()) return;
    was = v.raw();
    out[n++] = ParamChange::Level(t, fixture, param, v);
  };
  const auto angle = [&](Param param, Q16_16 v) {
    int32_t& was = shown.shown[static_cast<int>(param)];
    if (shown.reported && was == v.raw()) return;
    was = v.raw();
    out[n++] = ParamChange::Angle(t, fixture, param, v);
  };
  const DmxFixtureValues& v = shown.values;
  level(Param::kDimmer, v.shutter_open ? ScaledDimmer(v.dimmer, dimmer_scale_q15) : Q1_15::FromRaw(0));
  const int pan_deg = p.pan_range_deg > 0 ? p.pan_range_deg : kDefaultPanRangeDeg;
  const int tilt_deg = p.tilt_range_deg > 0 ? p.tilt_range_deg : kDefaultTiltRangeDeg;
  // What the type has no channel for is not reported: the bake's aim stays
  // for a fixed par, its colour for a dimmer-only type.
  const auto has = [&](DmxFunction f) { return p.Offset(f) >= 0; };
  if (has(DmxFunction::kPan)) angle(Param::kPan, ConsoleToDegrees(v.pan16, pan_deg << 16));
  if (has(DmxFunction::kTilt)) angle(Param::kTilt, ConsoleToDegrees(v.tilt16, tilt_deg << 16));
  if (has(DmxFunction::kRed) || has(DmxFunction::kGreen) || has(DmxFunction::kBlue) || has(DmxFunction::kWhite) ||
      has(DmxFunction::kCyan) || has(DmxFunction::kMagenta) || has(DmxFunction::kYellow) || p.has_wheel) {
    level(Param::kRed, v.r);
    level(Param::kGreen, v.g);
    level(Param::kBlue, v.b);
  }
  if (v.beam_angle.raw() > 0) angle(Param::kZoom, v.beam_angle);
  if (has(DmxFunction::kX)) level(Param::kX, v.x);
  if (has(DmxFunction::kY)) level(Param::kY, v.y);
  if (has(DmxFunction::kSize)) level(Param::kSize, v.size);
  shown.reported = true;
  return n;
}

size_t DmxChanges::Collect(int64_t now_us, ParamChange* out, size_t capacity) {
  if (pending_next_ >= pending_count_) {
    pending_count_ = pending_next_ = 0;
    {
      std::lock_guard<std::mutex> lock(mu_);
      for (size_t i = 0; i < fixtures_.size(); ++i) {
        snapshot_[i].values = fixtures_[i].values;
        snapshot_[i].last_frame_us = fixtures_[i].last_frame_us;
        snapshot_[i].received = fixtures_[i].received;
      }
    }
    for (size_t i = 0; i < snapshot_.size(); ++i) {
      Fixture& f = snapshot_[i];
      if (!f.received) continue;  // no frame for it yet: the bake's look stays
      pending_count_ += Report(i, LossDimmerScaleQ15(f, now_us), f, &pending_[pending_count_]);
    }
  }
  size_t n = 0;
  while (n < capacity && pending_next_ < pending_count_) out[n++] = pending_[pending_next_++];
  return n;
}

}  // namespace relight::hal
