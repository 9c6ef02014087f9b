#include "core/error.hpp"

#include <nlohmann/json.hpp>

namespace hrisim::core {

std::string_view to_string(ErrorCode code) {
  switch (code) {
    case ErrorCode::bad_request: return "bad_request";
    case ErrorCode::unauthorized: return "unauthorized";
    case ErrorCode::forbidden: return "forbidden";
    case ErrorCode::not_found: return "not_found";
    case ErrorCode::method_not_allowed: return "method_not_allowed";
    case ErrorCode::conflict: return "conflict";
    case ErrorCode::payload_too_large: return "payload_too_large";
    case ErrorCode::unsupported_media_type: return "unsupported_media_type";
    case ErrorCode::headers_too_large: return "headers_too_large";
    case ErrorCode::unavailable: return "unavailable";
    case ErrorCode::storage: return "storage";
    case ErrorCode::internal: return "internal";
  }
  return "internal";
}

int http_status(ErrorCode code) {
  switch (code) {
    case ErrorCode::bad_request: return 400;
    case ErrorCode::unauthorized: return 401;
    case ErrorCode::forbidden: return 403;
    case ErrorCode::not_found: return 404;
    case ErrorCode::method_not_allowed: return 405;
    case ErrorCode::conflict: return 409;
    case ErrorCode::payload_too_large: return 413;
    case ErrorCode::unsupported_media_type: return 415;
    case ErrorCode::headers_too_large: return 431;
    case ErrorCode::unavailable: return 503;
    case ErrorCode::storage: return 500;
    case ErrorCode::internal: return 500;
  }
  return 500;
}

Error::Error(ErrorCode code, const std::string& message) : std::runtime_error(message), code_(code) {}

Error::Error(ErrorCode code, const std::string& message, nlohmann::json details)
    : std::runtime_error(message), code_(code), details_(std::make_shared<const nlohmann::json>(std::move(details))) {}

Error::Error(ErrorCode code, const std::string& message, const std::string& key, const std::string& value)
    : Error(code, message, nlohmann::json{{key, value}}) {}

const nlohmann::json& Error::details() const {
  static const nlohmann::json kNone = nlohmann::json::object();
  return details_ ? *details_ : kNone;
}

nlohmann::json Error::to_json() const {
  nlohmann::json body{{"code", to_string(code_)}, {"message", what()}};
  if (!details().empty()) body["details"] = details();
  return {{"error", std::move(body)}};
}

}  // namespace hrisim::core
