#include "startup_memory.h"

#include <malloc.h>

#include <cstdint>

#include "relight/base/clock.h"
#include "relight/base/log.h"
#include "relight/base/status.h"
#include "relight/render/compiler_pages.h"

namespace relight::daemon {

namespace {

// glibc raises its mmap threshold to the size of each mmapped block freed
// (up to 32 MB), so once the bake's first sections are freed every later
// array comes from the heap, and freeing the 16-bit copy of an 8-bit basis or
// a luminaire's direct-term inputs leaves holes the next arrays do not fit:
// the heap grew 10.6 MB during Engine::Open with 20 MB of it free. A fixed
// threshold keeps every block of 128 KiB or more in its own mapping, handed
// back when freed. The trim threshold goes up with it (a fixed mmap threshold
// leaves the trim threshold at 128 KiB, and llvmpipe's bins, freed at the
// top of the heap after each frame, then shrank and regrew it 44 times a
// frame); relightd trims at its own moments (ReleaseFreeHeapPages).
void MapLargeBlocksApart() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
  mallopt(M_TRIM_THRESHOLD, 64 * 1024 * 1024);
#endif
}

}  // namespace

Status CompileShadersThenReleaseCompiler(const DaemonConfig& config, cli::FramePipeline* pipeline) {
  MapLargeBlocksApart();
  // Shaders first, then the compiler out, then (the caller) the bake: never resident together.
  RELIGHT_RETURN_IF_ERROR(pipeline->WarmUp(config.width, config.height));
  const int64_t start_us = MonotonicUs();
  render::PagesReleased released;
  const Status st = render::ReleaseShaderCompilerPages(&released);
  if (!st.ok()) {
    Log(LogLevel::kInfo, "relightd: shader compiler pages kept: %s", st.ToString().c_str());
    return Status::Ok();
  }
  Log(LogLevel::kInfo,
      "relightd: shaders compiled; the compiler's pages handed back to the kernel before the bake is read (%d "
      "read-only mappings, %.1f MB mapped), %.1f ms",
      released.mappings, static_cast<double>(released.bytes) / 1e6,
      static_cast<double>(MonotonicUs() - start_us) / 1e3);
  return Status::Ok();
}

void ReleaseFreeHeapPages() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace relight::daemon
