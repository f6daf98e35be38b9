// Errors in the runtime are values: every fallible call returns a Status (or
// fills an out-parameter and returns one). The runtime builds without
// exceptions. A Status carries a code and a short static or owned message that
// says what and where ("bake: section MESH: size 12 exceeds file").
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace relight {

enum class StatusCode : uint8_t {
  kOk = 0,
  kInvalidArgument,  // a caller passed a value outside its documented range
  kNotFound,         // a file, luminaire or grid that does not exist
  kIoError,          // open/read/write/rename failed (errno in the message)
  kCorrupt,          // a bake whose bytes fail validation (size, checksum, range)
  kUnsupported,      // a valid file of a version or feature this build lacks
  kOutOfRange,       // a value that would saturate or overflow a fixed format
  kInternal,         // an invariant broke: a bug, reported instead of aborting
};

const char* StatusCodeName(StatusCode code);

class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}
  static Status Ok() { return Status(); }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }
  // "corrupt: bake: section MESH: ..." — for logs and CLI errors.
  std::string ToString() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

// Builds "what: detail" messages without iostreams.
std::string StrFormat(const char* fmt, ...) __attribute__((format(printf, 1, 2)));

}  // namespace relight

// A broken invariant is a bug, not an input error: report and abort.
#define RELIGHT_CHECK(cond)                                                        \
  do {                                                                             \
    if (!(cond)) {                                                                 \
      std::fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
      std::abort();                                                                \
    }                                                                              \
  } while (0)

#define RELIGHT_RETURN_IF_ERROR(expr)       \
  do {                                      \
    ::relight::Status _st = (expr);         \
    if (!_st.ok()) return _st;              \
  } while (0)
