// The strict JSON parse behind every scene file and `--set` value: nlohmann's DOM parser driven
// through a SAX handler that also tracks the key path, so a duplicate key (nlohmann would keep
// the last one silently), a number that overflows a double and a syntax error are each reported
// with the key in the scene's terms and the line and column.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace apiclab {

// Why a text is not strict JSON: the cause, the key path of the value at fault (empty at the
// top level) and "line L, column C" (empty for a duplicate key, which has no position).
struct JsonError {
  std::string cause, path, position;
  // One line: "key 'materials.0.E' appears twice ...", "key 'domain.dx': number 1e400 is out of
  // range for a double (line 3, column 9)", "malformed JSON at line 2, column 5 (near key
  // 'domain'): syntax error ...".
  std::string text() const;
};

// Parses `text` into `out`. On failure returns false and fills `error`. The ordered_json form
// keeps the keys in the order written (sweep specs: the axes' order).
bool parse_json_strict(const std::string& text, nlohmann::json& out, JsonError& error);
bool parse_json_strict(const std::string& text, nlohmann::ordered_json& out, JsonError& error);

}  // namespace apiclab
