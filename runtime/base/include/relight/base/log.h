// One-line log messages from hal backends and the daemon ("relightd: modbus-tcp:
// client 127.0.0.1:40312 connected"). Goes to stderr unless a test or the
// daemon installs another sink. Thread-safe: lines from several threads do
// not interleave.
#pragma once

#include <functional>
#include <string>

namespace relight {

enum class LogLevel { kInfo, kWarning, kError };

void Log(LogLevel level, const char* fmt, ...) __attribute__((format(printf, 2, 3)));
// Replaces the sink (nullptr restores stderr); returns nothing.
void SetLogSink(std::function<void(LogLevel, const std::string&)> sink);

}  // namespace relight
