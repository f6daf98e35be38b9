// Reading photometric files as text: lines (LF, CRLF or CR), numbers in a
// token stream that remembers each token's line, and strict number parsing,
// so every reader error can name the file, the line and what was expected.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace relight::baker {

// The file's lines without their line ends; line n of the file is [n - 1].
std::vector<std::string> SplitLines(const std::string& text);
std::string Trim(const std::string& s);
// A number for messages: "400", "2.5", "0.9687".
std::string Fmt(double v);

// The whole of `s` (surrounding blanks allowed) as a finite number.
// decimal_comma: "99,8" reads as 99.8 (EULUMDAT files from the wild).
bool ParseNumber(const std::string& s, bool decimal_comma, double* out);

// Numbers separated by blanks (and by commas unless decimal_comma), over
// lines [first_line, end) of a file, 0-based. Memory is a small multiple of
// the text's size, which the callers bound (kMaxPhotometricFileBytes,
// bounded_read.h); no count in the text sizes anything here.
class NumberStream {
 public:
  NumberStream(const std::vector<std::string>& lines, size_t first_line, std::string path,
               bool decimal_comma);

  bool AtEnd() const { return next_ >= tokens_.size(); }
  size_t remaining() const { return tokens_.size() - next_; }
  // The line (1-based) of the next token, or of the file's last line at the end.
  int line() const;

  // Next token as a number; throws SceneError "file:line: expected <what>,
  // got 'x'" or "...: expected <what>, but the file ends".
  double Number(const std::string& what);
  // Next token as an integer in [lo, hi] (written as 3 or 3.0).
  int Integer(const std::string& what, int lo, int hi);
  // Anything left over is an error naming what the counts said.
  void ExpectEnd(const std::string& what_came_before);
  // Before sizing anything from counts a file declares: at least `count`
  // values must follow, else "file:<last line>: <what> on line <count_line>
  // declares N values, but the file ends after M ...". Cheap (the tokens are already split), so a header
  // claiming 10000 x 10000 angles fails here instead of in the allocator.
  void Require(size_t count, const std::string& what, int count_line) const;

  [[noreturn]] void Fail(int line, const std::string& what) const;

 private:
  struct Token {
    std::string text;
    int line;
  };
  std::vector<Token> tokens_;
  size_t next_ = 0;
  int last_line_ = 0;
  std::string path_;
  bool decimal_comma_;
};

}  // namespace relight::baker
