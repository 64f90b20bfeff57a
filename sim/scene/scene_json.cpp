#include "sim/scene/scene_json.hpp"

#include <set>
#include <vector>

#include "sim/scene/message_text.hpp"

namespace apiclab {
namespace {

using nlohmann::json;

// Line and column (1-based) of a byte offset.
std::string position_text(const std::string& text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

// What nlohmann's parser expected next, in the project's words (its "expected '}'" part).
std::string expected_text(const std::string& what) {
  const auto at = what.find("; expected ");
  if (at == std::string::npos) return "";
  const std::string e = what.substr(at + 11);
  if (e == "string literal") return "a key in double quotes";
  if (e.find("literal") != std::string::npos) return "a value";
  if (e == "end of input") return "the end of the text";
  return e.size() <= 40 ? e : "";
}

// What the parser met instead, from its "unexpected '}'" part, else the token it stopped at.
std::string unexpected_text(const std::string& what, const std::string& token) {
  const auto at = what.find("- unexpected ");
  if (at == std::string::npos) return "'" + token + "'";
  std::string name = what.substr(at + 13, what.find(';', at) - at - 13);
  if (name == "number literal") return "a number";
  if (name == "string literal") return "a string";
  if (name.find("literal") != std::string::npos) return "a value";
  return name.size() <= 40 ? name : "'" + token + "'";
}

// A syntax error in the project's words, from the token the parser stopped at (the one
// translation of nlohmann's parse_error text: "syntax error while parsing value - invalid
// literal; last read: '/'" never reaches the user).
std::string syntax_cause(const std::string& text, std::size_t position, const std::string& token,
                         const std::string& what) {
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    return "the text is empty (a scene is a JSON object, { ... })";
  if (!token.empty() && token[0] == '/')
    return "comments (// and /* */) are not part of JSON: remove them";
  if (!token.empty() && token[0] == '\'') return "text takes double quotes (\"...\"), not single";
  if (what.find("control character") != std::string::npos)
    return "a string holds a line break or control character (write it as \\n, \\t)";
  if (what.find("invalid string") != std::string::npos)
    return "a string holds an invalid escape or character";
  if (what.find("invalid number") != std::string::npos) return "'" + token + "' is not a number";
  if (token.empty() || position > text.size() || what.find("end of input;") != std::string::npos)
    return "the text ends before the JSON does (a { or [ left open, or a value missing)";
  const std::string expected = expected_text(what);
  std::string cause = "unexpected " + unexpected_text(what, token);
  if (what.find("invalid literal") != std::string::npos)
    cause += " (text takes double quotes; the literals are true, false and null)";
  else if (!expected.empty())
    cause += ", expected " + expected;
  return cause;
}

// Forwards every event to nlohmann's DOM builder; keeps the path of the value being read and
// the keys seen in each open object. J: nlohmann::json, or ordered_json where key order counts.
template <class J>
class StrictSax {
 public:
  StrictSax(J& out, const std::string& text) : dom_(out, false), text_(text) {}

  bool null() { return value() && dom_.null(); }
  bool boolean(bool v) { return value() && dom_.boolean(v); }
  bool number_integer(json::number_integer_t v) { return value() && dom_.number_integer(v); }
  bool number_unsigned(json::number_unsigned_t v) { return value() && dom_.number_unsigned(v); }
  bool number_float(json::number_float_t v, const json::string_t& s) {
    return value() && dom_.number_float(v, s);
  }
  bool string(json::string_t& v) { return value() && dom_.string(v); }
  bool binary(json::binary_t& v) { return value() && dom_.binary(v); }
  bool start_object(std::size_t n) {
    if (!value() || too_deep()) return false;
    frames_.push_back({true, "", -1, {}});
    return dom_.start_object(n);
  }
  bool key(json::string_t& k) {
    Frame& f = frames_.back();
    f.key = k;
    if (!f.keys.insert(k).second) {
      error_ = {"appears twice (JSON would keep only the last; remove one)", path(), ""};
      return false;
    }
    return dom_.key(k);
  }
  bool end_object() {
    frames_.pop_back();
    return dom_.end_object();
  }
  bool start_array(std::size_t n) {
    if (!value() || too_deep()) return false;
    frames_.push_back({false, "", -1, {}});
    return dom_.start_array(n);
  }
  bool end_array() {
    frames_.pop_back();
    return dom_.end_array();
  }
  bool parse_error(std::size_t position, const std::string& token,
                   const nlohmann::detail::exception& ex) {
    // The failing value was not counted yet: in an array it is the next element.
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
    const bool overflow = ex.id == 406;  // out_of_range.406: number overflow
    // A long token is quoted cut short, so the message stays one readable line.
    const std::string shown = token.size() <= 40 ? token : token.substr(0, 30) + "...";
    error_ = {overflow ? "number " + shown + " is out of range for a double"
                       : syntax_cause(text_, position, shown, ex.what()),
              path(), position_text(text_, position > 0 ? position - 1 : 0)};
    return false;
  }
  const JsonError& error() const { return error_; }

 private:
  struct Frame {
    bool object;
    std::string key;
    long index;
    std::set<std::string> keys;
  };
  // A scene nests 5 levels deep. nlohmann's parser is iterative, but dumping or destroying a
  // value recurses once per level: 200,000 '[' overflowed the stack (fuzz finding 2).
  static constexpr std::size_t kMaxDepth = 64;
  bool too_deep() {
    if (frames_.size() < kMaxDepth) return false;
    error_ = {"nests deeper than " + std::to_string(kMaxDepth) + " levels", path(), ""};
    return true;
  }
  // A value starts: in an array, it is the next element.
  bool value() {
    if (!frames_.empty() && !frames_.back().object) ++frames_.back().index;
    return true;
  }
  std::string path() const {
    std::string p;
    for (const Frame& f : frames_) {
      std::string part = f.object ? f.key : (f.index >= 0 ? std::to_string(f.index) : "");
      if (part.empty()) continue;
      p += (p.empty() ? "" : ".") + part;
    }
    return p;
  }

  nlohmann::detail::json_sax_dom_parser<J> dom_;
  const std::string& text_;
  std::vector<Frame> frames_;
  JsonError error_;
};

}  // namespace

std::string JsonError::text() const {
  // A key is any text: quoted on one readable line (sim/scene/message_text.hpp).
  const std::string path = message_text(this->path);
  if (position.empty()) return "key '" + path + "' " + cause;  // a duplicate key
  if (cause.rfind("number ", 0) == 0 && !path.empty())
    return "key '" + path + "': " + cause + " (" + position + ")";
  return "malformed JSON at " + position + (path.empty() ? "" : " (near key '" + path + "')") +
         ": " + cause;
}

namespace {

template <class J>
bool parse_strict(const std::string& text, J& out, JsonError& error) {
  out = J();
  StrictSax<J> sax(out, text);
  if (J::sax_parse(text, &sax)) return true;
  error = sax.error();
  if (error.cause.empty()) error.cause = "malformed JSON";
  out = J();
  return false;
}

}  // namespace

bool parse_json_strict(const std::string& text, json& out, JsonError& error) {
  return parse_strict(text, out, error);
}

bool parse_json_strict(const std::string& text, nlohmann::ordered_json& out, JsonError& error) {
  return parse_strict(text, out, error);
}

}  // namespace apiclab
