// The patch reader's view of a TOML table: typed getters that throw
// PatchError "file:line: what: why" (ParsePatch turns it into a Status).
// Shared by the reader's files (patch_toml.cc, emitter_toml.cc); not public.
#pragma once

#include <toml++/toml.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <string>

#include "relight/hal/patch.h"

namespace relight::hal::patch_reader {

// Thrown inside the patch reader only; ParsePatch turns it into a Status.
struct PatchError {
  std::string message;
};

class Table {
 public:
  Table(const toml::table& table, const std::string& where, std::string what)
      : t_(table), where_(where), what_(std::move(what)) {}

  int line() const { return static_cast<int>(t_.source().begin.line); }

  [[noreturn]] void Fail(const toml::node* node, const std::string& why) const {
    const int line_no = node != nullptr ? static_cast<int>(node->source().begin.line) : line();
    throw PatchError{where_ + ":" + std::to_string(line_no) + ": " + what_ + ": " + why};
  }

  void CheckKeys(std::initializer_list<const char*> allowed) const {
    for (const auto& [key, node] : t_) {
      bool known = false;
      for (const char* a : allowed) known = known || key.str() == a;
      if (!known) {
        std::string list;
        for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
        Fail(&node, "unknown key '" + std::string(key.str()) + "' (known: " + list + ")");
      }
    }
  }

  bool Has(const char* key) const { return t_.contains(key); }

  std::string String(const char* key, const std::string& fallback, bool required = false) const {
    const toml::node* node = t_.get(key);
    if (node == nullptr) {
      if (required) Fail(nullptr, std::string("missing '") + key + "'");
      return fallback;
    }
    const auto v = node->value<std::string>();
    if (!node->is_string() || !v) Fail(node, std::string("'") + key + "' must be a string");
    return *v;
  }

  int64_t Int(const char* key, int64_t fallback, int64_t lo, int64_t hi, bool required = false) const {
    const toml::node* node = t_.get(key);
    if (node == nullptr) {
      if (required) Fail(nullptr, std::string("missing '") + key + "'");
      return fallback;
    }
    if (!node->is_integer()) Fail(node, std::string("'") + key + "' must be an integer");
    const int64_t v = *node->value<int64_t>();
    if (v < lo || v > hi) {
      Fail(node, std::string("'") + key + "' must be in " + std::to_string(lo) + ".." + std::to_string(hi) +
                     ", got " + std::to_string(v));
    }
    return v;
  }

  // `unit` (e.g. " degrees") follows the range in messages.
  double Number(const char* key, double fallback, double lo, double hi, const char* unit = "") const {
    const toml::node* node = t_.get(key);
    if (node == nullptr) return fallback;
    if (!node->is_number()) Fail(node, std::string("'") + key + "' must be a number");
    const double v = *node->value<double>();
    if (!std::isfinite(v) || v < lo || v > hi) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "'%s' must be in %g..%g%s, got %g", key, lo, hi, unit, v);
      Fail(node, buf);
    }
    return v;
  }

  bool Bool(const char* key, bool fallback) const {
    const toml::node* node = t_.get(key);
    if (node == nullptr) return fallback;
    if (!node->is_boolean()) Fail(node, std::string("'") + key + "' must be true or false");
    return *node->value<bool>();
  }

  const toml::array* Array(const char* key) const {
    const toml::node* node = t_.get(key);
    if (node == nullptr) return nullptr;
    if (!node->is_array()) Fail(node, std::string("'") + key + "' must be an array");
    return node->as_array();
  }

  const toml::node* Node(const char* key) const { return t_.get(key); }

 private:
  const toml::table& t_;
  const std::string& where_;
  std::string what_;
};

// Each [[name]] entry, or an error if `name` is not an array of tables.
template <typename Fn>
void ForEachTable(const toml::table& root, const std::string& where, const char* name, Fn fn) {
  const toml::node* node = root.get(name);
  if (node == nullptr) return;
  const toml::array* arr = node->as_array();
  if (arr == nullptr || !arr->is_array_of_tables()) {
    throw PatchError{where + ":" + std::to_string(node->source().begin.line) + ": '" + name +
                     "' must be an array of tables ([[" + name + "]])"};
  }
  int index = 0;
  for (const toml::node& item : *arr) fn(*item.as_table(), ++index);
}

inline const toml::table* Section(const toml::table& root, const std::string& where, const char* name) {
  const toml::node* node = root.get(name);
  if (node == nullptr) return nullptr;
  if (!node->is_table()) {
    throw PatchError{where + ":" + std::to_string(node->source().begin.line) + ": '" + name +
                     "' must be a table ([" + name + "])"};
  }
  return node->as_table();
}

// Shared by [[fixture]] and [[emitter]] (patch_toml.cc): the name (as text
// names fixtures), and the input controls: modbus_base, registers (else
// `default_layout`), dimmer_curve, fade_ms.
void ParseName(const Table& t, std::string* name);
void ParseControls(const Table& t, const RegisterLayout& default_layout, FixturePatch* f);
// [[emitter]] (emitter_toml.cc).
void ParseEmitter(const Table& t, Patch* patch);

}  // namespace relight::hal::patch_reader
