// llvmpipe compiles its shaders with LLVM, so libLLVM is mapped into every
// process that renders. Loading it resolves hundreds of thousands of symbols
// and runs its static constructors, which pulls about 45 MB of its read-only
// pages into the process (measured on the stage: docs/performance.md,
// "Memory after the first frames"). Once the renderer's shaders are compiled
// (relightd: FramePipeline::WarmUp, before the bake is read), those pages
// are not read again. The kernel would drop them under memory pressure
// anyway; this asks it to do so now (madvise MADV_PAGEOUT), so the box's
// memory and relightd's RSS show what the show really holds.
//
// MADV_PAGEOUT never loses data: clean file pages are re-read from the file
// if touched again (a later shader compile, e.g. a pick render, costs a few
// page faults), dirty ones are only ever swapped. Linux 5.4 and later. A
// page another process maps too (a second renderer on the box) is shared
// and stays resident: the kernel pages out only pages mapped once.
//
// No allocation; reads /proc/self/maps through a fixed buffer. Call from one
// thread; other threads may run.
#pragma once

#include <cstdint>

#include "relight/base/status.h"

namespace relight::render {

struct PagesReleased {
  uint64_t bytes = 0;   // the length of the mappings advised (resident or not)
  int mappings = 0;     // read-only mappings of matching files
};

// Advises MADV_PAGEOUT on every read-only mapping of a file whose path
// contains `path_part` (non-empty). kUnsupported when the kernel lacks
// MADV_PAGEOUT; kIoError when /proc/self/maps cannot be read. No match is
// not an error (mappings == 0).
Status ReleaseMappedFilePages(const char* path_part, PagesReleased* released);

// The shader compiler's: every mapped libLLVM (llvmpipe's).
Status ReleaseShaderCompilerPages(PagesReleased* released);

}  // namespace relight::render
