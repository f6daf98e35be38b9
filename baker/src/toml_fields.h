// Typed, checked access to one TOML table of a scene file. Every failure
// throws SceneError naming file:line, the object ("luminaire 'spot1'") and
// what was expected, e.g.
//   scene.toml:12: luminaire 'spot1': sh_degree must be an integer 0..22, got 23
#pragma once

#include <toml++/toml.h>

#include <cstdint>
#include <initializer_list>
#include <limits>
#include <optional>
#include <string>

#include "relight/baker/scene.h"

namespace relight::baker {

// An interval for numbers, phrased in messages as "in [0, 1)" or "> 0".
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  bool Contains(double x) const;
  std::string Describe() const;
};
inline constexpr Range kAnyNumber{};
Range Positive();                        // > 0
Range NonNegative();                     // >= 0
Range Closed(double lo, double hi);      // [lo, hi]
Range HalfOpen(double lo, double hi);    // [lo, hi)
Range OpenClosed(double lo, double hi);  // (lo, hi]

// The line a node starts on (0 when toml++ does not know it).
int LineOf(const toml::node& node);
// A short rendering of a node's value for "got ...": 20, 1.5, "abc", an array of 2.
std::string Describe(const toml::node& node);
// A number with no trailing zeros ("0.5", "20", "1e-06").
std::string FormatNumber(double x);
bool IsIdentifier(const std::string& name);
// 'name', for messages.
inline std::string Quoted(const std::string& s) { return "'" + s + "'"; }
// Direction vectors shorter than this (metres) count as zero.
inline constexpr double kMinVectorM = 1e-6;

class TomlFields {
 public:
  // `what` names the object in messages ("luminaire 'spot1'", "[scene]").
  TomlFields(const toml::table& table, std::string file, std::string what);

  const toml::table& table() const { return table_; }
  const std::string& file() const { return file_; }
  const std::string& what() const { return what_; }
  void set_what(std::string what) { what_ = std::move(what); }
  // Names the object from its `key` string when it has one ("luminaire 'spot1'"),
  // so even its first error (say an unknown key) can say which object it is.
  void NameFrom(const char* key, const std::string& kind);
  int line() const { return LineOf(table_); }

  // Any key not in `allowed` is an error (typos must not pass silently).
  void CheckKeys(std::initializer_list<const char*> allowed) const;
  bool Has(const char* key) const { return table_.contains(key); }
  // The node at `key`; a missing key is an error.
  const toml::node& Required(const char* key) const;
  // Line of `key`'s value, or of the table when it is absent.
  int LineOfKey(const char* key) const;

  // Numbers accept TOML integers and floats and must be finite. Without a
  // fallback the key is required.
  double Number(const char* key, const Range& range = kAnyNumber,
                std::optional<double> fallback = std::nullopt) const;
  int64_t Integer(const char* key, int64_t lo, int64_t hi,
                  std::optional<int64_t> fallback = std::nullopt) const;
  bool Bool(const char* key, bool fallback) const;
  std::string String(const char* key, std::optional<std::string> fallback = std::nullopt) const;
  // A name the runtime can address: [A-Za-z0-9_-]+.
  std::string Identifier(const char* key) const;
  Vec3 Vector(const char* key, std::optional<Vec3> fallback = std::nullopt) const;
  const toml::table& Table(const char* key) const;
  const toml::array& Array(const char* key) const;

  // Reads `node` as exactly 3 finite numbers; `name` phrases the message
  // ("corner 2", "position").
  Vec3 ReadVec3(const toml::node& node, const std::string& name) const;
  // Reads `node` as a number in `range`; `name` phrases the message.
  double ReadNumber(const toml::node& node, const std::string& name, const Range& range) const;

  // Errors at a node (its line) or at the table.
  [[noreturn]] void Fail(const toml::node& at, const std::string& message) const;
  [[noreturn]] void Fail(const std::string& message) const;
  [[noreturn]] void FailAtLine(int line, const std::string& message) const;

 private:
  const toml::table& table_;
  std::string file_;
  std::string what_;
};

}  // namespace relight::baker
