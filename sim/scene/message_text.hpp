// Text from an input quoted inside a one-line error message: control characters escaped (a JSON
// key may hold "\n", decoded to a line break: fuzz_scene found the message split in two) and a
// long text cut short (fuzzed inputs of 200,000 brackets were echoed whole).
#pragma once
#include <cstdio>
#include <string>

namespace apiclab {

// The characters message_text escapes (for a quick test that a text needs it).
inline const std::string kControlCharacters = [] {
  std::string s;
  for (int c = 1; c < 0x20; ++c) s += char(c);
  return s + char(0) + char(0x7f);
}();

// `keep`: the length above which the text is cut; std::string::npos keeps it whole.
inline std::string message_text(const std::string& s, std::size_t keep = 120) {
  const bool cut = keep != std::string::npos && s.size() > keep && keep > 20;
  const std::size_t n = cut ? keep - 20 : s.size();
  std::string out;
  out.reserve(n + 32);
  for (std::size_t i = 0; i < n; ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c < 0x20 || c == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", c);
      out += hex;
    } else {
      out += char(c);
    }
  }
  if (cut) out += "... (" + std::to_string(s.size()) + " characters)";
  return out;
}

}  // namespace apiclab
