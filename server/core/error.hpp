#pragma once
// The one error type of hrisim: a machine-readable code, a message for people, and details that
// locate the problem (a JSON pointer, an XML line, a file path), as in {"error":{code,message,details}}.
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <string_view>

namespace hrisim::core {

/// Error categories; each maps to one HTTP status (see http_status()).
enum class ErrorCode {
  bad_request,        ///< malformed or invalid input (400)
  unauthorized,       ///< no or a wrong bearer token (401)
  forbidden,          ///< authenticated or not, this is not allowed, e.g. a foreign Origin (403)
  not_found,          ///< unknown id or path (404)
  method_not_allowed, ///< path exists, method does not (405)
  conflict,           ///< state does not allow the operation (409)
  payload_too_large,  ///< body over the limit (413)
  unsupported_media_type,  ///< a body of a type the route does not take (415)
  headers_too_large,  ///< request header fields over the limit (431)
  unavailable,        ///< temporarily unable to serve, e.g. too many connections (503)
  storage,            ///< database failure (500)
  internal,           ///< a bug (500)
};

/// Stable snake_case name of a code, as used in JSON errors.
std::string_view to_string(ErrorCode code);
/// HTTP status a code is answered with.
int http_status(ErrorCode code);

class Error : public std::runtime_error {
 public:
  Error(ErrorCode code, const std::string& message, nlohmann::json details = nlohmann::json::object());

  ErrorCode code() const { return code_; }
  const nlohmann::json& details() const { return details_; }
  /// {"error":{"code":..,"message":..,"details":..}}
  nlohmann::json to_json() const;

 private:
  ErrorCode code_;
  nlohmann::json details_;
};

}  // namespace hrisim::core
