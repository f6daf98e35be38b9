// Fixture settings on the command line ("--set FIXTURE.PARAM=VALUE", the
// syntax of hal/'s ParseParamText) for the tools, and applying parameter
// changes to an Engine.
#pragma once

#include <string>
#include <vector>

#include "relight/engine/engine.h"
#include "relight/hal/param_text.h"

namespace relight::cli {

// A --set argument as plain numbers (for the float64 baker): pan, tilt,
// roll and zoom in degrees, levels 0..1; colour has three values, the rest one.
struct SetArg {
  std::string fixture;
  std::string param;  // pan | tilt | roll | zoom | dimmer | r | g | b | colour
  std::vector<double> values;
};
bool ParseSetArg(const std::string& text, SetArg* out, std::string* error);

// Applies one change to the engine's fixture state. Fails with a message
// naming the fixture if the bake has no luminaire of that name, listing the
// ones it has.
bool ApplyChange(Engine& engine, const ParamChange& change, std::string* error);
// Parses and applies one --set argument.
bool ApplySetText(Engine& engine, const std::string& text, std::string* error);

}  // namespace relight::cli
