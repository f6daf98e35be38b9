// Fuzz target: the scene file (LoadScene, as relight-bake reads it), TOML and
// everything it names. LoadScene takes a path, so the bytes are written to a
// scratch folder that also holds links to fixtures/living_room (an OBJ and
// its MTL) and fixtures/photometry (IES and LDT files): the seeds from
// fixtures/ name those, and the fuzzer can reach the readers through them.
// Meshing a parsed scene is included (the mesher's size checks, issue 17
// item 4); the radiosity solve is not.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "mesher.h"
#include "relight/baker/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string kPath = [] {
    const std::string dir = relight::fuzz::ScratchDir();
    for (const char* sub : {"living_room", "photometry"}) {
      const std::string target = std::string(RELIGHT_SOURCE_DIR) + "/fixtures/" + sub;
      if (symlink(target.c_str(), (dir + "/" + sub).c_str()) != 0) return std::string();
    }
    return dir + "/scene.toml";
  }();
  if (kPath.empty()) return 0;
  relight::fuzz::WriteScratchFile("scene.toml", data, size);
  try {
    const relight::baker::Scene scene = relight::baker::LoadScene(kPath);
    (void)relight::baker::BuildMesh(scene);
  } catch (const relight::baker::SceneError&) {
  }
  return 0;
}
