#pragma once
// Small helpers for the text readers (OFF, OBJ, ASCII STL, XYZ, ASCII PLY): they read from bytes in
// memory, which need not end in '\0', so numbers are copied out before strtod sees them.

#include <cstddef>
#include <cstdlib>
#include <string>
#include <string_view>

namespace poreshell::text {

inline bool is_space(char ch) {
  return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\n' || ch == '\v' || ch == '\f';
}

// The number `token` spells exactly; false for anything else. strtod also reads "nan" and "inf", so that
// those are reported as non-finite coordinates rather than as unreadable text.
inline bool parse_double(std::string_view token, double& out) {
  char buffer[128];
  if (token.empty() || token.size() >= sizeof buffer) return false;
  token.copy(buffer, token.size());
  buffer[token.size()] = '\0';
  char* end = nullptr;
  out = std::strtod(buffer, &end);
  return end == buffer + token.size();
}

// Splits text into lines ('\n', a trailing '\r' dropped) and lines into tokens, without copying.
class Lines {
 public:
  explicit Lines(std::string_view text) : rest_(text), done_(text.empty()) {}

  // The next line and its number (from 1); false at the end.
  bool next(std::string_view& line) {
    if (done_) return false;
    const std::size_t end = rest_.find('\n');
    line = rest_.substr(0, end);
    if (end == std::string_view::npos) {
      done_ = true;
      rest_ = {};
    } else {
      rest_.remove_prefix(end + 1);
      done_ = rest_.empty();
    }
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ++number_;
    return true;
  }
  std::size_t number() const { return number_; }

 private:
  std::string_view rest_;
  std::size_t number_ = 0;
  bool done_ = false;
};

// The next whitespace-separated token of `line`, removed from it; empty at the end.
inline std::string_view next_token(std::string_view& line) {
  std::size_t i = 0;
  while (i < line.size() && is_space(line[i])) ++i;
  std::size_t j = i;
  while (j < line.size() && !is_space(line[j])) ++j;
  const std::string_view token = line.substr(i, j - i);
  line.remove_prefix(j);
  return token;
}

// A short, printable quote of untrusted text for a one-line message: control bytes become '?'.
inline std::string quote(std::string_view text, std::size_t max = 40) {
  std::string out(text.substr(0, max));
  for (char& ch : out)
    if (static_cast<unsigned char>(ch) < 0x20 || static_cast<unsigned char>(ch) >= 0x7f) ch = '?';
  if (text.size() > max) out += "...";
  return out;
}

}  // namespace poreshell::text
