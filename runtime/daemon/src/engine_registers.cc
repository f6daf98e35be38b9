#include "engine_registers.h"

namespace relight::daemon {

// The holding registers that show the engine's state (an emitter's: its
// patch's start levels), for the servers' start.
std::vector<uint16_t> RegistersFor(const Engine& engine, const hal::Patch& patch, const hal::RegisterMap& map) {
  std::vector<uint16_t> regs(static_cast<size_t>(map.holding_count()), 0);
  for (int f = 0; f < map.fixture_count(); ++f) {
    const hal::FixturePatch& fixture = map.fixture(f);
    uint16_t* block = &regs[static_cast<size_t>(fixture.modbus_base)];
    if (fixture.emitter >= 0) {
      const hal::EmitterPatch& e = patch.emitters[static_cast<size_t>(fixture.emitter)];
      FixtureState state;
      state.dimmer = Q1_15::FromRaw(static_cast<int16_t>(e.dimmer_q15));
      for (int c = 0; c < 3; ++c) state.rgb[c] = Q1_15::FromRaw(static_cast<int16_t>(e.rgb_q15[c]));
      map.Encode(state, f, block);
      const hal::Channel places[3] = {hal::Channel::kX, hal::Channel::kY, hal::Channel::kSize};
      const int32_t levels[3] = {e.x_q15, e.y_q15, e.size_q15};
      for (int k = 0; k < 3; ++k) {
        if (fixture.layout.Has(places[k])) block[fixture.layout.OffsetOf(places[k])] = hal::Register16FromLevelQ15(levels[k]);
      }
      continue;
    }
    const int lum = engine.FindLuminaire(fixture.name);
    if (lum < 0) continue;
    map.Encode(engine.state(lum), f, block);
  }
  return regs;
}

// The bake's luminaires as the patch sees them: names and console ranges.
std::vector<hal::LuminaireConsole> Luminaires(const Engine& engine) {
  std::vector<hal::LuminaireConsole> out;
  for (const BakeLuminaire& lum : engine.bake().luminaires) out.push_back({lum.name, lum.pan_range, lum.tilt_range});
  return out;
}

}  // namespace relight::daemon
