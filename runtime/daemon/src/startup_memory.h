// What relightd's start-up needed and the show does not, handed back to the
// kernel (DaemonConfig::release_startup_memory), in two steps of Open:
//  0. (first) the heap keeps blocks of 128 KiB or more in their own mappings,
//     so what the bake's reading and the engine's set-up free goes back at
//     once instead of leaving holes in the heap;
//  1. after FramePipeline::WarmUp has had llvmpipe compile every shader the
//     frames use, and before the bake is read: the shader compiler's pages
//     (render/compiler_pages.h), so they are never resident beside the bake;
//  2. once the bake is read, and again after the second drawn frame: the
//     heap's free pages left by reading the bake and by the first frames.
// Each logs what it did.
#pragma once

#include "daemon.h"
#include "frame_pipeline.h"

namespace relight::daemon {

// Steps 0 and 1: the heap's thresholds, FramePipeline::WarmUp at the
// config's frame size, then the compiler's pages out. Errors are WarmUp's.
Status CompileShadersThenReleaseCompiler(const DaemonConfig& config, cli::FramePipeline* pipeline);
void ReleaseFreeHeapPages();

}  // namespace relight::daemon
