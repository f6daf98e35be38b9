// Drives an Engine from a replay script in script time (not wall-clock):
// frame i shows the state at i / fps seconds, so the same script always
// gives the same frames.
#pragma once

#include <functional>
#include <cstdint>
#include <string>

#include "relight/engine/engine.h"

namespace relight::cli {

// Renders one frame per 1/fps seconds of script time until the last change
// has been shown; `render_to(path)` updates, draws and writes one frame and
// returns 0 or an exit code. `pattern` holds one printf %d for the frame
// number (e.g. "frames/frame_%04d.png"). Returns a process exit code.
// With a non-empty `sheet_path`, also writes every frame tiled into one PNG
// (4 per row, half size), `frame_rgb` being the buffer render_to fills.
struct ContactSheet {
  std::string path;
  const uint8_t* frame_rgb = nullptr;
  int width = 0, height = 0;
};
int RenderReplay(Engine& engine, const std::string& script_path, double fps, const std::string& pattern,
                 const std::function<int(const std::string&)>& render_to, const ContactSheet& sheet);

}  // namespace relight::cli
