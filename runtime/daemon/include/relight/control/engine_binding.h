// The last step of a change: a typed ParamChange whose `fixture` is an
// engine luminaire index goes to the engine's typed setter. Names are
// resolved to luminaire indices once, at load (BindNames), never per change.
// Used by relightd (through ChangePath), relight-render --set and --replay,
// and relight-replay-hash alike.
//
// Thread safety: none (the engine's). No allocation on ApplyToEngine.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "relight/base/param.h"
#include "relight/base/status.h"
#include "relight/engine/engine.h"

namespace relight::control {

// Calls the setter of change.param for luminaire change.fixture: degrees
// for pan, tilt, roll and zoom (the other angle kept), levels clamped to 0..1
// for dimmer and colour (the other channels kept); an unchanged zoom is no
// call. kInvalidArgument for a bad index; SetZoom's kUnsupported for a new
// zoom on a luminaire without one.
Status ApplyToEngine(Engine& engine, const ParamChange& change);

// The bake's luminaire names, in index order.
std::vector<std::string> LuminaireNames(const Engine& engine);

// For each of `names`, its luminaire index. kNotFound "WHERE: no luminaire
// 'x' in the bake (it has: ...)" for the first name the bake lacks.
Status BindNames(const Engine& engine, const std::vector<std::string>& names, const std::string& where,
                 std::vector<uint16_t>* out);

}  // namespace relight::control
