// Checked access to scene TOML tables: types, ranges, unknown keys, and
// messages that say file:line, which object, what was expected and what was found.
#include "toml_fields.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

namespace relight::baker {

namespace {

// Levenshtein distance, for "did you mean" on unknown keys.
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, substitute});
    }
  }
  return row[b.size()];
}

std::string Quote(const char* key) { return std::string("'") + key + "'"; }

}  // namespace

bool Range::Contains(double x) const {
  const bool above = lo_open ? x > lo : x >= lo;
  const bool below = hi_open ? x < hi : x <= hi;
  return above && below;
}

std::string Range::Describe() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi) {
    return std::string("in ") + (lo_open ? "(" : "[") + FormatNumber(lo) + ", " + FormatNumber(hi) +
           (hi_open ? ")" : "]");
  }
  if (has_lo) return (lo_open ? "> " : ">= ") + FormatNumber(lo);
  if (has_hi) return (hi_open ? "< " : "<= ") + FormatNumber(hi);
  return "finite";
}

Range Positive() { return Range{0, kAnyNumber.hi, true, false}; }
Range NonNegative() { return Range{0, kAnyNumber.hi, false, false}; }
Range Closed(double lo, double hi) { return Range{lo, hi, false, false}; }
Range HalfOpen(double lo, double hi) { return Range{lo, hi, false, true}; }
Range OpenClosed(double lo, double hi) { return Range{lo, hi, true, false}; }

int LineOf(const toml::node& node) { return static_cast<int>(node.source().begin.line); }

std::string FormatNumber(double x) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", x);
  return buf;
}

std::string Describe(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::integer:
      return std::to_string(node.as_integer()->get());
    case toml::node_type::floating_point: {
      const double x = node.as_floating_point()->get();
      std::string s = FormatNumber(x);
      // Show that it is a float where the digits alone would not ("8.0").
      if (std::isfinite(x) && s.find_first_of(".e") == std::string::npos) s += ".0";
      return s;
    }
    case toml::node_type::boolean:
      return node.as_boolean()->get() ? "true" : "false";
    case toml::node_type::string: {
      std::string s = node.as_string()->get();
      if (s.size() > 40) s = s.substr(0, 37) + "...";
      return "\"" + s + "\"";
    }
    case toml::node_type::array:
      return "an array of " + std::to_string(node.as_array()->size());
    case toml::node_type::table:
      return "a table";
    case toml::node_type::date:
    case toml::node_type::time:
    case toml::node_type::date_time:
      return "a date/time";
    case toml::node_type::none:
      break;
  }
  return "nothing";
}

bool IsIdentifier(const std::string& name) {
  if (name.empty()) return false;
  return std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

TomlFields::TomlFields(const toml::table& table, std::string file, std::string what)
    : table_(table), file_(std::move(file)), what_(std::move(what)) {}

void TomlFields::FailAtLine(int line, const std::string& message) const {
  throw SceneError(file_, line, what_.empty() ? message : what_ + ": " + message);
}
void TomlFields::Fail(const toml::node& at, const std::string& message) const {
  FailAtLine(LineOf(at), message);
}
void TomlFields::Fail(const std::string& message) const { FailAtLine(line(), message); }

void TomlFields::NameFrom(const char* key, const std::string& kind) {
  const toml::node* node = table_.get(key);
  if (node != nullptr && node->is_string()) what_ = kind + " '" + node->as_string()->get() + "'";
}

void TomlFields::CheckKeys(std::initializer_list<const char*> allowed) const {
  for (auto&& [key, node] : table_) {
    const std::string name(key.str());
    const bool known =
        std::any_of(allowed.begin(), allowed.end(), [&](const char* a) { return name == a; });
    if (known) continue;
    std::string best;
    size_t best_distance = 3;  // suggest only near misses
    std::string list;
    for (const char* a : allowed) {
      list += (list.empty() ? "" : ", ") + std::string(a);
      // A prefix ("peak" for "peak_cd") counts as a near miss too.
      const std::string candidate(a);
      const bool prefix = name.size() >= 3 && candidate.rfind(name, 0) == 0;
      const size_t d = prefix ? 1 : EditDistance(name, candidate);
      if (d < best_distance) {
        best_distance = d;
        best = a;
      }
    }
    FailAtLine(static_cast<int>(key.source().begin.line),
               "unknown key '" + name + "'" +
                   (best.empty() ? "" : " (did you mean '" + best + "'?)") +
                   "; expected one of: " + list);
  }
}

const toml::node& TomlFields::Required(const char* key) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) Fail("missing key " + Quote(key));
  return *node;
}

int TomlFields::LineOfKey(const char* key) const {
  const toml::node* node = table_.get(key);
  return node != nullptr ? LineOf(*node) : line();
}

double TomlFields::ReadNumber(const toml::node& node, const std::string& name,
                              const Range& range) const {
  double x = 0;
  if (const auto* i = node.as_integer()) {
    x = static_cast<double>(i->get());
  } else if (const auto* f = node.as_floating_point()) {
    x = f->get();
  } else {
    Fail(node, name + " must be a number " + range.Describe() + ", got " + Describe(node));
  }
  if (!std::isfinite(x) || !range.Contains(x)) {
    Fail(node, name + " must be a number " + range.Describe() + ", got " + Describe(node));
  }
  return x;
}

double TomlFields::Number(const char* key, const Range& range,
                          std::optional<double> fallback) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) {
    if (!fallback) Fail("missing key " + Quote(key) + " (a number " + range.Describe() + ")");
    return *fallback;
  }
  return ReadNumber(*node, key, range);
}

int64_t TomlFields::Integer(const char* key, int64_t lo, int64_t hi,
                            std::optional<int64_t> fallback) const {
  const std::string expect = hi == std::numeric_limits<int64_t>::max()
                                 ? "an integer >= " + std::to_string(lo)
                                 : "an integer " + std::to_string(lo) + ".." + std::to_string(hi);
  const toml::node* node = table_.get(key);
  if (node == nullptr) {
    if (!fallback) Fail("missing key " + Quote(key) + " (" + expect + ")");
    return *fallback;
  }
  const auto* i = node->as_integer();
  if (i == nullptr || i->get() < lo || i->get() > hi) {
    Fail(*node, std::string(key) + " must be " + expect + ", got " + Describe(*node));
  }
  return i->get();
}

bool TomlFields::Bool(const char* key, bool fallback) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) return fallback;
  const auto* b = node->as_boolean();
  if (b == nullptr)
    Fail(*node, std::string(key) + " must be true or false, got " + Describe(*node));
  return b->get();
}

std::string TomlFields::String(const char* key, std::optional<std::string> fallback) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) {
    if (!fallback) Fail("missing key " + Quote(key) + " (a string)");
    return *fallback;
  }
  const auto* s = node->as_string();
  if (s == nullptr) Fail(*node, std::string(key) + " must be a string, got " + Describe(*node));
  return s->get();
}

std::string TomlFields::Identifier(const char* key) const {
  const std::string name = String(key);
  if (!IsIdentifier(name)) {
    Fail(Required(key), std::string(key) +
                            " must be a non-empty name of letters, digits, '_' and '-', got " +
                            Describe(Required(key)));
  }
  return name;
}

Vec3 TomlFields::ReadVec3(const toml::node& node, const std::string& name) const {
  const auto* array = node.as_array();
  if (array == nullptr || array->size() != 3) {
    Fail(node, name + " must be an array of 3 numbers [x, y, z], got " + Describe(node));
  }
  Vec3 v{};
  for (size_t k = 0; k < 3; ++k) v[k] = ReadNumber(*array->get(k), name + " element", kAnyNumber);
  return v;
}

Vec3 TomlFields::Vector(const char* key, std::optional<Vec3> fallback) const {
  const toml::node* node = table_.get(key);
  if (node == nullptr) {
    if (!fallback) Fail("missing key " + Quote(key) + " (an array of 3 numbers)");
    return *fallback;
  }
  return ReadVec3(*node, key);
}

const toml::table& TomlFields::Table(const char* key) const {
  const toml::node& node = Required(key);
  const auto* t = node.as_table();
  if (t == nullptr)
    Fail(node, std::string(key) + " must be a table { ... }, got " + Describe(node));
  return *t;
}

const toml::array& TomlFields::Array(const char* key) const {
  const toml::node& node = Required(key);
  const auto* a = node.as_array();
  if (a == nullptr) Fail(node, std::string(key) + " must be an array, got " + Describe(node));
  return *a;
}

}  // namespace relight::baker
