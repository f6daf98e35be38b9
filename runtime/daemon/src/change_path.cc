#include "relight/control/change_path.h"

#include "relight/base/log.h"
#include "relight/control/engine_binding.h"

namespace relight::control {
namespace {

constexpr size_t kPollBatch = 256;
constexpr int64_t kMaxWarnings = 5;  // per kind: a flood of bad changes must not flood the log

}  // namespace

Status ChangePath::Bind(Engine* engine, const std::vector<hal::FixturePatch>& fixtures, const ChangePath* previous,
                        const std::vector<hal::EmitterPatch>& emitters, const std::string& where) {
  const int luminaire_count = engine->luminaire_count();
  std::vector<std::string> names;
  for (const hal::FixturePatch& f : fixtures) {
    if (f.emitter < 0) names.push_back(f.name);
  }
  std::vector<uint16_t> lum_of_name;
  RELIGHT_RETURN_IF_ERROR(BindNames(*engine, names, "patch", &lum_of_name));
  if (luminaire_count + emitters.size() > static_cast<size_t>(kMaxFixtures)) {
    return Status(StatusCode::kInvalidArgument, where + ": more luminaires and emitters than 65535");
  }
  // A patch fixture's slot: its luminaire, or after every luminaire for an emitter.
  std::vector<uint16_t> luminaires;
  size_t next_name = 0;
  for (const hal::FixturePatch& f : fixtures) {
    if (f.emitter >= 0 && static_cast<size_t>(f.emitter) >= emitters.size()) {
      return Status(StatusCode::kInvalidArgument, where + ": fixture '" + f.name + "' names an emitter not given");
    }
    luminaires.push_back(f.emitter >= 0 ? static_cast<uint16_t>(luminaire_count + f.emitter) : lum_of_name[next_name++]);
  }
  EmitterBinding binding;
  RELIGHT_RETURN_IF_ERROR(binding.Bind(engine, emitters, where));
  // Slot = luminaire: a luminaire the patch does not name fades with defaults.
  std::vector<hal::FixturePatch> by_slot(static_cast<size_t>(luminaire_count) + emitters.size());
  for (int i = 0; i < luminaire_count; ++i) by_slot[static_cast<size_t>(i)].name = engine->bake().luminaires[static_cast<size_t>(i)].name;
  for (size_t e = 0; e < emitters.size(); ++e) by_slot[static_cast<size_t>(luminaire_count) + e] = emitters[e].control;
  for (size_t i = 0; i < fixtures.size(); ++i) by_slot[luminaires[i]] = fixtures[i];
  auto fader = std::make_unique<Fader>(by_slot);
  for (int slot = 0; slot < luminaire_count; ++slot) fader->Reset(slot, engine->state(slot));
  for (size_t e = 0; e < emitters.size(); ++e) {
    const hal::EmitterPatch& p = emitters[e];
    int32_t values[kParamCount] = {};
    values[static_cast<int>(Param::kDimmer)] = p.dimmer_q15;
    values[static_cast<int>(Param::kRed)] = p.rgb_q15[0];
    values[static_cast<int>(Param::kGreen)] = p.rgb_q15[1];
    values[static_cast<int>(Param::kBlue)] = p.rgb_q15[2];
    values[static_cast<int>(Param::kX)] = p.x_q15;
    values[static_cast<int>(Param::kY)] = p.y_q15;
    values[static_cast<int>(Param::kSize)] = p.size_q15;
    fader->ResetValues(luminaire_count + static_cast<int>(e), values, /*emitter=*/true);
  }
  if (previous != nullptr && previous->fader_) fader->CopyRampsFrom(*previous->fader_);
  engine_ = engine;
  fader_ = std::move(fader);
  patch_luminaires_ = std::move(luminaires);
  emitters_ = std::move(binding);
  batch_.assign(kPollBatch, ParamChange());
  outputs_.assign(static_cast<size_t>(fader_->slot_count()) * kParamCount, ParamChange());
  if (previous != nullptr) {
    dropped_ = previous->dropped_;
    rejected_ = previous->rejected_;
  }
  return Status::Ok();
}

std::vector<std::string> ChangePath::SlotNames() const {
  std::vector<std::string> names = LuminaireNames(*engine_);
  for (int e = 0; e < emitters_.count(); ++e) names.push_back(fader_->slot_name(engine_->luminaire_count() + e));
  return names;
}

int64_t ChangePath::Poll(const BoundInput& input, int64_t source_now_us, int64_t time_us) {
  int64_t newest = 0;
  size_t n;
  do {
    n = input.source->Poll(source_now_us, batch_.data(), batch_.size());
    for (size_t i = 0; i < n; ++i) {
      ParamChange c = batch_[i];
      if (!input.luminaire_of.empty()) {
        if (c.fixture >= input.luminaire_of.size()) {
          if (dropped_++ < kMaxWarnings) {
            Log(LogLevel::kWarning, "relightd: %s: a change for fixture %u, which it does not have; ignored",
                input.source->Name(), static_cast<unsigned>(c.fixture));
          }
          continue;
        }
        c.fixture = input.luminaire_of[c.fixture];
      }
      if (!fader_->SetTarget(c, time_us)) {
        if (dropped_++ < kMaxWarnings) {
          Log(LogLevel::kWarning, "relightd: %s: no luminaire %u in the bake; change ignored", input.source->Name(),
              static_cast<unsigned>(c.fixture));
        }
        continue;
      }
      if (c.time_us > newest) newest = c.time_us;
    }
  } while (n == batch_.size());
  return newest;
}

size_t ChangePath::Apply(int64_t time_us) {
  const size_t n = fader_->Step(time_us, outputs_.data());
  const int luminaire_count = engine_->luminaire_count();
  for (size_t i = 0; i < n; ++i) {
    const ParamChange& c = outputs_[i];
    if (c.fixture >= luminaire_count) {
      // An emitter: gathered here, handed over below, one engine call each.
      if (!emitters_.Set(c.fixture - luminaire_count, c.param, c.level.raw()) && rejected_++ < kMaxWarnings) {
        Log(LogLevel::kError, "relightd: %s.%s: an emitter has dimmer, r, g, b, x, y and size only",
            fader_->slot_name(c.fixture).c_str(), ParamName(c.param));
      }
      continue;
    }
    const Status st = ApplyToEngine(*engine_, c);
    if (!st.ok() && rejected_++ < kMaxWarnings) {
      Log(LogLevel::kError, "relightd: %s.%s: %s", engine_->bake().luminaires[c.fixture].name.c_str(),
          ParamName(c.param), st.ToString().c_str());
    }
  }
  Status error;
  const int failed = emitters_.Flush(&error);
  if (failed > 0 && (rejected_ += failed) - failed < kMaxWarnings) {
    Log(LogLevel::kError, "relightd: emitter: %s", error.ToString().c_str());
  }
  return n;
}

}  // namespace relight::control
