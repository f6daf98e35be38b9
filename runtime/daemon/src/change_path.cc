#include "relight/control/change_path.h"

#include "relight/base/log.h"
#include "relight/control/engine_binding.h"

namespace relight::control {
namespace {

constexpr size_t kPollBatch = 256;
constexpr int64_t kMaxWarnings = 5;  // per kind: a flood of bad changes must not flood the log

}  // namespace

Status ChangePath::Bind(Engine* engine, const std::vector<hal::FixturePatch>& fixtures, const ChangePath* previous) {
  std::vector<std::string> names;
  for (const hal::FixturePatch& f : fixtures) names.push_back(f.name);
  std::vector<uint16_t> luminaires;
  RELIGHT_RETURN_IF_ERROR(BindNames(*engine, names, "patch", &luminaires));
  // Slot = luminaire: a luminaire the patch does not name fades with defaults.
  std::vector<hal::FixturePatch> by_luminaire(static_cast<size_t>(engine->luminaire_count()));
  for (size_t i = 0; i < by_luminaire.size(); ++i) by_luminaire[i].name = engine->bake().luminaires[i].name;
  for (size_t i = 0; i < fixtures.size(); ++i) by_luminaire[luminaires[i]] = fixtures[i];
  auto fader = std::make_unique<Fader>(by_luminaire);
  for (int slot = 0; slot < fader->slot_count(); ++slot) fader->Reset(slot, engine->state(slot));
  if (previous != nullptr && previous->fader_) fader->CopyRampsFrom(*previous->fader_);
  engine_ = engine;
  fader_ = std::move(fader);
  patch_luminaires_ = std::move(luminaires);
  batch_.assign(kPollBatch, ParamChange());
  outputs_.assign(static_cast<size_t>(fader_->slot_count()) * kParamCount, ParamChange());
  if (previous != nullptr) {
    dropped_ = previous->dropped_;
    rejected_ = previous->rejected_;
  }
  return Status::Ok();
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
  for (size_t i = 0; i < n; ++i) {
    const Status st = ApplyToEngine(*engine_, outputs_[i]);
    if (!st.ok() && rejected_++ < kMaxWarnings) {
      Log(LogLevel::kError, "relightd: %s.%s: %s", engine_->bake().luminaires[outputs_[i].fixture].name.c_str(),
          ParamName(outputs_[i].param), st.ToString().c_str());
    }
  }
  return n;
}

}  // namespace relight::control
