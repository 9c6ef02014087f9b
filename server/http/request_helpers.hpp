#pragma once
// Small pieces every route needs: query values, and JSON bodies refused when nested too deep (what
// their fields may be is the request contract's: request_contract.hpp).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "http/router.hpp"

namespace hrisim::http {

/// The value of `key` in a raw query string, decoded as browsers encode a form (%XX, and + for a
/// space); core::Error(bad_request) for a malformed escape.
std::optional<std::string> query_value(const std::string& query, const std::string& key);

/// An integer query parameter in [low, high], or `fallback` when absent; 400 naming it otherwise.
std::int64_t integer_query(const Request& request, const std::string& key, std::int64_t low, std::int64_t high, std::int64_t fallback);

/// The request body as a JSON object: 400 with the line and column of a syntax error, for a body
/// nested too deep (core::check_json_nesting), or for anything but an object. An empty body is an empty object.
nlohmann::json json_object_body(const Request& request);

/// ?format=: json (the default) or csv; 400 naming the parameter otherwise.
std::string json_or_csv_format(const Request& request);

/// What CSV downloads are sent as.
inline constexpr const char* kCsvContentType = "text/csv; charset=utf-8";

/// 200 with `body` of `content_type`, saved by browsers as `filename`.
Response download(std::string body, const std::string& content_type, const std::string& filename);

}  // namespace hrisim::http
