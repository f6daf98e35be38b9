#include "photometric_text.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "relight/baker/scene.h"

namespace relight::baker {

std::vector<std::string> SplitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::string current;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\r' || c == '\n') {
      lines.push_back(current);
      current.clear();
      if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') ++i;
    } else {
      current += c;
    }
  }
  if (!current.empty()) lines.push_back(current);
  return lines;
}

std::string Trim(const std::string& s) {
  const char* blanks = " \t\f\v";
  const size_t a = s.find_first_not_of(blanks);
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(blanks);
  return s.substr(a, b - a + 1);
}

std::string Fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

bool ParseNumber(const std::string& s, bool decimal_comma, double* out) {
  std::string t = Trim(s);
  if (t.empty()) return false;
  if (decimal_comma && t.find('.') == std::string::npos) {
    const size_t comma = t.find(',');
    if (comma != std::string::npos && t.find(',', comma + 1) == std::string::npos) t[comma] = '.';
  }
  // strtod also takes "inf", "nan" and hex: only plain decimal numbers here.
  for (char c : t) {
    const bool ok = (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+' || c == 'e' ||
                    c == 'E';
    if (!ok) return false;
  }
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (end != t.c_str() + t.size() || errno == ERANGE || !std::isfinite(v)) return false;
  *out = v;
  return true;
}

NumberStream::NumberStream(const std::vector<std::string>& lines, size_t first_line,
                           std::string path, bool decimal_comma)
    : path_(std::move(path)), decimal_comma_(decimal_comma) {
  last_line_ = static_cast<int>(lines.size());
  for (size_t i = first_line; i < lines.size(); ++i) {
    const std::string& s = lines[i];
    size_t k = 0;
    while (k < s.size()) {
      const auto separator = [&](char c) {
        return c == ' ' || c == '\t' || c == '\f' || c == '\v' || (!decimal_comma_ && c == ',');
      };
      while (k < s.size() && separator(s[k])) ++k;
      const size_t start = k;
      while (k < s.size() && !separator(s[k])) ++k;
      if (k > start) tokens_.push_back({s.substr(start, k - start), static_cast<int>(i) + 1});
    }
  }
}

int NumberStream::line() const { return AtEnd() ? last_line_ : tokens_[next_].line; }

void NumberStream::Fail(int line, const std::string& what) const {
  throw SceneError(path_, line, what);
}

double NumberStream::Number(const std::string& what) {
  if (AtEnd()) Fail(last_line_, "expected " + what + ", but the file ends (truncated?)");
  const Token& t = tokens_[next_];
  double v = 0;
  if (!ParseNumber(t.text, decimal_comma_, &v)) {
    Fail(t.line, "expected " + what + " (a number), got '" + t.text + "'");
  }
  ++next_;
  return v;
}

int NumberStream::Integer(const std::string& what, int lo, int hi) {
  const int line_of = line();
  const double v = Number(what);
  if (v != std::floor(v) || v < lo || v > hi) {
    Fail(line_of, "expected " + what + " (an integer " + std::to_string(lo) + ".." +
                      std::to_string(hi) + "), got " + tokens_[next_ - 1].text);
  }
  return static_cast<int>(v);
}

void NumberStream::Require(size_t count, const std::string& what, int count_line) const {
  if (remaining() >= count) return;
  // Named at the end, where a truncated file's problem is, with the count's line.
  Fail(last_line_, what + " on line " + std::to_string(count_line) + " declares " +
                       std::to_string(count) + " values, but the file ends after " +
                       std::to_string(remaining()) + " (truncated, or is a count wrong?)");
}

void NumberStream::ExpectEnd(const std::string& what_came_before) {
  if (AtEnd()) return;
  Fail(tokens_[next_].line, std::to_string(remaining()) + " unexpected value(s) from '" +
                                tokens_[next_].text + "' on, after " + what_came_before +
                                " (do the counts match the data?)");
}

}  // namespace relight::baker
