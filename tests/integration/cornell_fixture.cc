#include "cornell_fixture.h"

#include <map>
#include <utility>

#include <gtest/gtest.h>

namespace relight::test {

const BakedScene& BakedFixture(const std::string& name, baker::DirectModeKind mode) {
  static std::map<std::pair<std::string, int>, std::unique_ptr<BakedScene>> cache;
  auto& slot = cache[{name, static_cast<int>(mode)}];
  if (!slot) {
    slot = std::make_unique<BakedScene>();
    slot->scene = baker::LoadScene(std::string(RELIGHT_SOURCE_DIR) + "/fixtures/" + name + ".toml");
    baker::BakeOptions options;
    options.direct_mode = mode;
    slot->baker = std::make_unique<baker::Baker>(slot->scene, options);
    slot->bake = slot->baker->Bake();
    slot->bake_path = ::testing::TempDir() + "/" + name + (mode == baker::DirectModeKind::kExact ? "_exact" : "_sh") +
                      ".rlb";
    const Status st = WriteBake(slot->bake, slot->bake_path);
    if (!st.ok()) ADD_FAILURE() << st.ToString();
  }
  return *slot;
}

}  // namespace relight::test
