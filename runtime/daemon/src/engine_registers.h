// What the Modbus servers and the patch see of the engine: the holding
// registers that show its state when they start, and the bake's luminaires
// as the patch binds them (names and console ranges).
//
// Thread safety: plain functions of their arguments.
#pragma once

#include <cstdint>
#include <vector>

#include "relight/engine/engine.h"
#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace relight::daemon {

// The holding registers of `map` for the engine's current state (an
// emitter's: its patch's start levels).
std::vector<uint16_t> RegistersFor(const Engine& engine, const hal::Patch& patch,
                                   const hal::RegisterMap& map);

// The bake's luminaires as the patch sees them.
std::vector<hal::LuminaireConsole> Luminaires(const Engine& engine);

}  // namespace relight::daemon
