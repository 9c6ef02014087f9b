#include "core/bounded_json.hpp"

#include <string>

#include "core/error.hpp"

namespace hrisim::core {

void check_json_nesting(std::string_view text) {
  int depth = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) {
        throw Error(ErrorCode::bad_request, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels", {{"limit", kMaxJsonDepth}});
      }
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

nlohmann::json parse_bounded_json(std::string_view text, std::string_view what) {
  try {
    check_json_nesting(text);
  } catch (const Error& e) {
    throw Error(ErrorCode::bad_request, std::string(what) + ": " + e.what(), e.details());
  }
  nlohmann::json value = nlohmann::json::parse(text, nullptr, false);
  if (value.is_discarded()) throw Error(ErrorCode::bad_request, std::string(what) + " is not JSON");
  return value;
}

}  // namespace hrisim::core
