// The Cornell box fixture baked once per test binary, in both direct modes,
// shared by the accuracy and golden-frame tests (baking is the slow part).
#pragma once

#include <memory>
#include <string>

#include "relight/bake/bake.h"
#include "relight/baker/baker.h"
#include "relight/baker/scene.h"

namespace relight::test {

struct BakedScene {
  baker::Scene scene;
  std::unique_ptr<baker::Baker> baker;
  Bake bake;
  std::string bake_path;  // the bake written to a temporary file
};

// Loads fixtures/<name>.toml, bakes it in the given mode (cached per mode).
const BakedScene& BakedFixture(const std::string& name, baker::DirectModeKind mode);

}  // namespace relight::test
