#pragma once
// JSON from outside the process — request bodies, and values read back from a database that came from
// elsewhere — parsed only after a linear check of its nesting: nlohmann's parser recurses once per
// level, so text nested tens of thousands deep would exhaust the stack.
#include <nlohmann/json.hpp>
#include <string_view>

namespace hrisim::core {

/// Deepest nesting of arrays and objects accepted in foreign JSON (a scenario needs about 10).
inline constexpr int kMaxJsonDepth = 64;

/// Throws core::Error(bad_request) for JSON nested deeper than kMaxJsonDepth (strings skipped), before
/// anything parses it.
void check_json_nesting(std::string_view text);

/// `text` parsed after check_json_nesting; core::Error(bad_request) naming `what` for text that is not
/// JSON or is nested too deep.
nlohmann::json parse_bounded_json(std::string_view text, std::string_view what);

}  // namespace hrisim::core
