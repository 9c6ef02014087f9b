#include "http/request_helpers.hpp"

#include <algorithm>
#include <charconv>
#include <sstream>

#include "core/bounded_json.hpp"
#include "core/error.hpp"
#include "core/json_schema.hpp"

namespace hrisim::http {

std::optional<std::string> query_value(const std::string& query, const std::string& key) {
  std::istringstream in(query);
  std::string pair;
  while (std::getline(in, pair, '&')) {
    const std::size_t equals = pair.find('=');
    if (pair.substr(0, equals) != key) continue;
    // As browsers encode a form: '+' for a space, %XX for the rest.
    std::string value = equals == std::string::npos ? "" : pair.substr(equals + 1);
    std::replace(value.begin(), value.end(), '+', ' ');
    return percent_decode(value);
  }
  return std::nullopt;
}

std::int64_t integer_query(const Request& request, const std::string& key, std::int64_t low, std::int64_t high, std::int64_t fallback) {
  const auto text = query_value(request.query, key);
  if (!text) return fallback;
  std::int64_t value = 0;
  const auto [end, ec] = std::from_chars(text->data(), text->data() + text->size(), value);
  if (ec != std::errc() || end != text->data() + text->size() || value < low || value > high) {
    throw core::Error(core::ErrorCode::bad_request, key + " must be an integer from " + std::to_string(low) + " to " + std::to_string(high),
                      {{"parameter", key}});
  }
  return value;
}

nlohmann::json json_object_body(const Request& request) {
  if (request.body.find_first_not_of(" \t\r\n") == std::string::npos) return nlohmann::json::object();
  core::check_json_nesting(request.body);
  nlohmann::json body;
  try {
    body = nlohmann::json::parse(request.body);
  } catch (const nlohmann::json::parse_error& e) {
    const auto [line, column] = core::line_and_column(request.body, e.byte > 0 ? e.byte - 1 : 0);
    throw core::Error(core::ErrorCode::bad_request, "invalid JSON at line " + std::to_string(line) + ", column " + std::to_string(column),
                      {{"line", line}, {"column", column}});
  } catch (const nlohmann::json::out_of_range&) {
    throw core::Error(core::ErrorCode::bad_request, "invalid JSON: a number is too large for a double");
  }
  if (!body.is_object()) throw core::Error(core::ErrorCode::bad_request, "the body must be a JSON object", {{"pointer", ""}});
  return body;
}

std::string json_or_csv_format(const Request& request) {
  const std::string format = query_value(request.query, "format").value_or("json");
  if (format != "json" && format != "csv") throw core::Error(core::ErrorCode::bad_request, "format must be json or csv", {{"parameter", "format"}});
  return format;
}

Response download(std::string body, const std::string& content_type, const std::string& filename) {
  Response response{200, content_type, std::move(body), {}, {}};
  response.headers.emplace_back("Content-Disposition", "attachment; filename=\"" + filename + "\"");
  return response;
}

}  // namespace hrisim::http
