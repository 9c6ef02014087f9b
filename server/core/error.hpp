#pragma once
// The one error type of hrisim: a machine-readable code, a message for people, and details that
// locate the problem (a JSON pointer, an XML line, a file path), as in {"error":{code,message,details}}.
#include <memory>
#include <nlohmann/json_fwd.hpp>
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
  Error(ErrorCode code, const std::string& message);
  /// With `details`, a JSON object saying where (a pointer, a line, a limit); who gives them includes
  /// <nlohmann/json.hpp>, the rest of the code only this header's forward declaration.
  Error(ErrorCode code, const std::string& message, nlohmann::json details);
  /// With the details {key: value}: what a caller names without JSON at hand (the simulation).
  Error(ErrorCode code, const std::string& message, const std::string& key, const std::string& value);

  ErrorCode code() const { return code_; }
  /// An empty object when none were given.
  const nlohmann::json& details() const;
  /// {"error":{"code":..,"message":..,"details":..}}
  nlohmann::json to_json() const;

 private:
  ErrorCode code_;
  std::shared_ptr<const nlohmann::json> details_;  ///< shared, so that copying a thrown error cannot throw
};

}  // namespace hrisim::core
