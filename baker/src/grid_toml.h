// One [[grid]] table of a scene file into a CalcGrid.
#pragma once

#include <map>
#include <string>

#include "relight/baker/scene.h"
#include "toml_fields.h"

namespace relight::baker {

// `grid_lines` holds the names seen so far (name -> line), so a repeated
// name is an error naming the first. Throws SceneError (file:line).
CalcGrid ReadGrid(const toml::table& table, const std::string& path,
                  std::map<std::string, int>* grid_lines);

}  // namespace relight::baker
