// Run-time surface emitters on the command line:
//   --emitter "SURFACE:L:x,y,z;x,y,z;x,y,z[;...]"   L in cd/m^2 (white), or R,G,B
// corners in metres, 3 to 8 of them around a convex polygon on the surface.
#pragma once

#include <string>

#include "relight/engine/engine.h"
#include "relight/engine/surface_emitter.h"

namespace relight::cli {

bool ParseEmitterArg(const std::string& text, SurfaceEmitterShape* shape, LightQ12 luminance[3],
                     std::string* error);
// Parses and places one --emitter in `slot` of the engine.
bool ApplyEmitterText(Engine& engine, int slot, const std::string& text, std::string* error);

}  // namespace relight::cli
