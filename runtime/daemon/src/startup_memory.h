// What relightd's start-up needed and the show does not, handed back to the
// kernel once frames flow (DaemonConfig::release_startup_memory): the shader
// compiler's pages (render/compiler_pages.h) and the heap's free pages left
// by reading the bake. Logs what it did. Call once, from the frame loop,
// after the second drawn frame: by then llvmpipe has compiled every shader
// the pipeline uses (the second draw at a camera adds the triangle-ID pass).
#pragma once

namespace relight::daemon {

void ReleaseStartupMemory();

}  // namespace relight::daemon
