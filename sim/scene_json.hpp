// The strict JSON parse behind every scene file and `--set` value: nlohmann's DOM parser driven
// through a SAX handler that also tracks the key path, so a duplicate key (nlohmann would keep
// the last one silently), a number that overflows a double and a syntax error are each reported
// with the key in the scene's terms and the line and column.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace apiclab {

// Parses `text` into `out`. On failure returns false and sets `error` to one line without the
// file name, e.g. "key 'materials.0.E' appears twice (line 7, column 31)" or "line 3, column 5:
// syntax error ...".
bool parse_json_strict(const std::string& text, nlohmann::json& out, std::string& error);

}  // namespace apiclab
