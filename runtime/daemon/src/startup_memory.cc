#include "startup_memory.h"

#include <malloc.h>

#include <cstdint>

#include "relight/base/clock.h"
#include "relight/base/log.h"
#include "relight/base/status.h"
#include "relight/render/compiler_pages.h"

namespace relight::daemon {

Status CompileShadersThenReleaseCompiler(const DaemonConfig& config, cli::FramePipeline* pipeline) {
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
