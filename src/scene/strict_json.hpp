// JSON text parsed strictly for scene files and --set values: a key twice in one object is an
// error (not "the last one wins"), and nesting has a limit, so a hostile file can neither hide a
// value nor exhaust the stack (issue 17).
#pragma once
#include <string>

#include <nlohmann/json.hpp>

namespace imx::scene_json {

// Objects and arrays nested deeper than this are an error. The deepest scene structure, a csg
// expression, allows 256 levels of operators (each an object holding "a" or an "of" array).
inline constexpr int kMaxJsonDepth = 1024;

// Parses `text`; throws imx::Error "origin: ..." for a duplicate key (naming its JSON path) or
// nesting past kMaxJsonDepth, and nlohmann::json::parse_error for malformed text.
nlohmann::json parse_strict_json(const std::string& text, const std::string& origin);

}  // namespace imx::scene_json
