// Chooses the input backends at start-up from the patch: each section the
// patch has ([modbus_tcp], [modbus_rtu], [modbus_poller], GPIO buttons or
// encoders, [replay]) gives one source. The sources are created, not
// started: the caller Start()s them and reports the first error.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "relight/hal/input_source.h"
#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace relight::hal {

// `patch` resolved; `initial`: the holding registers showing the engine's
// current state (RegisterMap::Encode per fixture); `replay_script`, if not
// empty, replaces the patch's [replay] script.
Status MakeInputSources(const Patch& patch, const RegisterMap& map, const std::vector<uint16_t>& initial,
                        const std::string& replay_script, std::vector<std::unique_ptr<InputSource>>* out);

}  // namespace relight::hal
