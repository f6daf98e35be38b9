// This process's memory as the kernel counts it, for the tools' and
// relightd's summaries (Linux /proc/self/status).
#pragma once

namespace relight {

// A "kB" field of /proc/self/status, e.g. "VmRSS" (resident now) or "VmHWM"
// (the resident peak), in kB of 1024 bytes; -1 if unknown (no /proc).
long ProcStatusKb(const char* field);

}  // namespace relight
