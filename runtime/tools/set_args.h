// Fixture settings on the command line ("--set FIXTURE.PARAM=VALUE", the
// syntax of hal/'s ParseParamText) for the tools. The name in an argument is
// resolved to the luminaire index once, when the argument is read; the
// change then goes through the control stage's binding
// (relight/control/engine_binding.h), the same one relightd uses.
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

// Applies one change whose `fixture` is a luminaire index (a replay source
// built with the bake's luminaire names) through the binding; on failure a
// message naming the luminaire and parameter.
bool ApplyChange(Engine& engine, const ParamChange& change, std::string* error);
// Parses one --set argument, resolves its fixture name (an unknown one: a
// message listing the bake's luminaires) and applies it.
bool ApplySetText(Engine& engine, const std::string& text, std::string* error);

}  // namespace relight::cli
