// Fuzz target: the OBJ geometry reader (ParseObj, as a scene's [[mesh]] is
// read), with the MTL files it names: the text is placed in a scratch folder
// next to one fixed material library (fuzz.mtl), so `mtllib fuzz.mtl` reads
// it and other names are missing files. The first byte chooses whether
// materials are read (a scene may give the material itself).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "obj_loader.h"
#include "relight/baker/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string kPath = [] {
    static const char kMtl[] = "newmtl wood\nKd 0.5 0.3 0.2\nnewmtl white\nKd 0.8 0.8 0.8\n";
    relight::fuzz::WriteScratchFile("fuzz.mtl", reinterpret_cast<const uint8_t*>(kMtl), sizeof kMtl - 1);
    return relight::fuzz::ScratchDir() + "/fuzz.obj";
  }();
  if (size < 1) return 0;
  const bool read_materials = (data[0] & 1) != 0;
  try {
    relight::baker::ParseObj(relight::fuzz::AsText(data + 1, size - 1), kPath, read_materials);
  } catch (const relight::baker::SceneError&) {
  }
  return 0;
}
