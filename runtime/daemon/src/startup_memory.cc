#include "startup_memory.h"

#include <malloc.h>

#include <cstdint>

#include "relight/base/clock.h"
#include "relight/base/log.h"
#include "relight/base/status.h"
#include "relight/render/compiler_pages.h"

namespace relight::daemon {

void ReleaseStartupMemory() {
  const int64_t start_us = MonotonicUs();
  render::PagesReleased released;
  const Status st = render::ReleaseShaderCompilerPages(&released);
  if (!st.ok()) Log(LogLevel::kInfo, "relightd: shader compiler pages kept: %s", st.ToString().c_str());
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
  Log(LogLevel::kInfo,
      "relightd: frames flowing; start-up memory handed back to the kernel (shader compiler: %d read-only "
      "mappings, %.1f MB mapped; free heap pages), %.1f ms",
      released.mappings, static_cast<double>(released.bytes) / 1e6,
      static_cast<double>(MonotonicUs() - start_us) / 1e3);
}

}  // namespace relight::daemon
