#include "relight/base/log.h"

#include <cstdarg>
#include <cstdio>
#include <mutex>

namespace relight {
namespace {

std::mutex& LogMutex() {
  static std::mutex mutex;
  return mutex;
}

std::function<void(LogLevel, const std::string&)>& Sink() {
  static std::function<void(LogLevel, const std::string&)> sink;
  return sink;
}

}  // namespace

void Log(LogLevel level, const char* fmt, ...) {
  char line[1024];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(line, sizeof line, fmt, args);
  va_end(args);
  std::lock_guard<std::mutex> lock(LogMutex());
  if (Sink()) {
    Sink()(level, line);
    return;
  }
  const char* tag = level == LogLevel::kError ? "error: " : level == LogLevel::kWarning ? "warning: " : "";
  std::fprintf(stderr, "%s%s\n", tag, line);
}

void SetLogSink(std::function<void(LogLevel, const std::string&)> sink) {
  std::lock_guard<std::mutex> lock(LogMutex());
  Sink() = std::move(sink);
}

}  // namespace relight
