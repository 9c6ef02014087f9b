#include "http/access.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <cctype>
#include <fstream>

#include "core/text.hpp"
#include "http/request_helpers.hpp"

namespace hrisim::http {
namespace {

std::string header(const Request& request, const std::string& name) {
  const auto found = request.headers.find(name);
  return found == request.headers.end() ? "" : found->second;
}

bool is_ip_address(const std::string& text) {
  unsigned char buffer[16];
  return inet_pton(AF_INET, text.c_str(), buffer) == 1 || inet_pton(AF_INET6, text.c_str(), buffer) == 1;
}

/// The host name of a Host header: without its port, an IPv6 address without its brackets.
std::string host_name(const std::string& host) {
  if (host.starts_with('[')) {
    const auto end = host.find(']');
    return end == std::string::npos ? host : host.substr(1, end - 1);
  }
  return core::lower_case(host.substr(0, host.rfind(':')));
}

/// A DNS-rebinding page reaches the server under a name the attacker controls; IP addresses,
/// localhost and the names the operator lists are the server's own.
bool host_allowed(const Request& request, const std::vector<std::string>& allowed) {
  const std::string host = header(request, "host");
  if (host.empty()) return true;  // HTTP/1.0; no browser sends a request without Host
  const std::string name = host_name(host);
  if (name == "localhost" || is_ip_address(name)) return true;
  return std::any_of(allowed.begin(), allowed.end(), [&](const std::string& entry) { return entry == "*" || core::lower_case(entry) == name; });
}

/// A browser's Origin is fine when it is the server's own — the same scheme, host and port — or
/// listed; clients that are not browsers send none.
bool origin_allowed(const Request& request, const std::vector<std::string>& allowed) {
  const std::string origin = header(request, "origin");
  if (origin.empty()) return true;
  if (origin == "http://" + header(request, "host")) return true;
  return std::find(allowed.begin(), allowed.end(), origin) != allowed.end();
}

bool is_upgrade(const Request& request) { return core::lower_case(header(request, "upgrade")) == "websocket"; }

bool changes_state(const Request& request) { return request.method != "GET" && request.method != "HEAD" && request.method != "OPTIONS"; }

/// Media types a page on another site cannot send without the browser asking first (CORS): JSON, XML
/// and YAML. text/plain, forms and no type at all it can.
bool safe_content_type(const Request& request) {
  std::string type = core::lower_case(header(request, "content-type"));
  type = type.substr(0, type.find(';'));
  type.erase(std::remove_if(type.begin(), type.end(), [](unsigned char c) { return std::isspace(c); }), type.end());
  return type == "application/json" || type == "application/xml" || type == "text/xml" || type == "application/yaml" ||
         type == "application/x-yaml" || type == "text/yaml" || type == "application/vnd.sqlite3" ||
         (type.starts_with("application/") && (type.ends_with("+json") || type.ends_with("+xml")));
}

/// Compares in time independent of where the strings differ, so a secret cannot be guessed byte by byte.
bool same_secret(const std::string& given, const std::string& expected) {
  unsigned char difference = given.size() == expected.size() ? 0 : 1;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    difference |= static_cast<unsigned char>(expected[i] ^ (i < given.size() ? given[i] : 0));
  }
  return difference == 0;
}

Caller caller_of(const Token& token) {
  return {token.name, token.role == Role::admin, token.role == Role::read};
}

Response refusal(core::ErrorCode code, const std::string& message, nlohmann::json details = nlohmann::json::object()) {
  Response response = Response::error(core::Error(code, message, std::move(details)));
  if (code == core::ErrorCode::unauthorized) response.headers.emplace_back("WWW-Authenticate", "Bearer realm=\"hrisim\"");
  return response;
}

/// The session a WebSocket path /api/v1/sessions/{id}/{socket} names (its own socket or a bridge's),
/// or empty.
std::string websocket_session(const std::string& path) {
  constexpr std::string_view kSessions = "/api/v1/sessions/";
  if (!path.starts_with(kSessions)) return "";
  const std::string_view rest = std::string_view(path).substr(kSessions.size());
  const std::size_t slash = rest.find('/');
  const bool one_socket_segment = slash != std::string_view::npos && slash > 0 && slash + 1 < rest.size() && rest.find('/', slash + 1) == std::string_view::npos;
  return one_socket_segment ? std::string(rest.substr(0, slash)) : "";
}

}  // namespace

Token parse_token(const std::string& text) {
  const auto first = text.find(':');
  if (first == std::string::npos) {
    if (text.size() < kMinimumTokenLength) {
      throw core::Error(core::ErrorCode::bad_request, "a token's secret needs at least " + std::to_string(kMinimumTokenLength) + " characters");
    }
    return {"", text, Role::admin};
  }
  Token token;
  token.name = text.substr(0, first);
  const auto second = text.find(':', first + 1);
  token.secret = text.substr(first + 1, second == std::string::npos ? std::string::npos : second - first - 1);
  const std::string role = second == std::string::npos ? "user" : text.substr(second + 1);
  if (token.name.empty() || !std::all_of(token.name.begin(), token.name.end(), [](unsigned char c) { return std::isalnum(c) || c == '-' || c == '_' || c == '.'; })) {
    throw core::Error(core::ErrorCode::bad_request, "a token's name is letters, digits, '-', '_' and '.' (NAME:SECRET[:ROLE])");
  }
  if (token.secret.size() < kMinimumTokenLength) {
    throw core::Error(core::ErrorCode::bad_request, "token '" + token.name + "': its secret needs at least " + std::to_string(kMinimumTokenLength) + " characters");
  }
  if (role == "user") {
    token.role = Role::user;
  } else if (role == "read") {
    token.role = Role::read;
  } else if (role == "admin") {
    token.role = Role::admin;
  } else {
    throw core::Error(core::ErrorCode::bad_request, "token '" + token.name + "': role is user, read or admin, not '" + role + "'");
  }
  return token;
}

std::vector<Token> read_token_file(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw core::Error(core::ErrorCode::bad_request, "cannot read the token file " + file.string());
  std::vector<Token> tokens;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    line.erase(0, line.find_first_not_of(" \t"));
    line.erase(line.find_last_not_of(" \t\r") + 1);
    if (line.empty() || line.starts_with('#')) continue;
    if (line.find(':') == std::string::npos) {
      throw core::Error(core::ErrorCode::bad_request, file.string() + ":" + std::to_string(number) + ": expected NAME:SECRET[:ROLE]");
    }
    try {
      tokens.push_back(parse_token(line));
    } catch (const core::Error& e) {
      throw core::Error(core::ErrorCode::bad_request, file.string() + ":" + std::to_string(number) + ": " + e.what());
    }
  }
  return tokens;
}

std::function<std::optional<Response>(Request&)> make_guard(AccessPolicy policy, std::shared_ptr<TicketBook> tickets) {
  return [policy = std::move(policy), tickets = std::move(tickets)](Request& request) -> std::optional<Response> {
    if (!host_allowed(request, policy.allowed_hosts)) {
      return refusal(core::ErrorCode::forbidden, "Host '" + header(request, "host") + "' is not this server's (see --allowed-hosts)",
                     {{"host", header(request, "host")}});
    }
    const bool api = request.path.starts_with("/api/");
    if (!api || request.path == "/api/v1/version") return std::nullopt;
    if ((changes_state(request) || is_upgrade(request)) && !origin_allowed(request, policy.allowed_origins)) {
      return refusal(core::ErrorCode::forbidden, "requests from origin " + header(request, "origin") + " are refused (see --allowed-origins)",
                     {{"origin", header(request, "origin")}});
    }
    if (policy.tokens.empty()) {
      request.caller = {};
      if ((request.method == "POST" || request.method == "PUT" || request.method == "PATCH") && !safe_content_type(request)) {
        return refusal(core::ErrorCode::unsupported_media_type,
                       "a " + request.method + " needs Content-Type: application/json (application/xml for an XML scenario, application/yaml for a YAML one) on a server without tokens",
                       {{"content_type", header(request, "content-type")}});
      }
      return std::nullopt;
    }
    // A browser opens a session's WebSocket with a ticket from an authenticated POST instead.
    if (const auto ticket = query_value(request.query, "ticket"); ticket && is_upgrade(request)) {
      const std::string session = websocket_session(request.path);
      if (const auto caller = session.empty() ? std::nullopt : tickets->redeem(*ticket, session)) {
        request.caller = *caller;
        return std::nullopt;
      }
    }
    const std::string authorization = header(request, "authorization");
    // RFC 7235: the scheme is case-insensitive; one or more spaces follow it.
    const auto space = authorization.find(' ');
    const std::string scheme = core::lower_case(authorization.substr(0, space));
    const auto secret = space == std::string::npos ? std::string::npos : authorization.find_first_not_of(' ', space);
    const std::string given = secret == std::string::npos ? "" : authorization.substr(secret);
    const Token* matched = nullptr;
    for (const Token& token : policy.tokens) {
      if (same_secret(given, token.secret) && scheme == "bearer") matched = &token;  // every token compared: no early exit
    }
    if (!matched) {
      return refusal(core::ErrorCode::unauthorized,
                     authorization.empty() ? "this route needs Authorization: Bearer <token>" : "the bearer token is wrong");
    }
    request.caller = caller_of(*matched);
    const bool ticket_request = request.method == "POST" && request.path.ends_with("/ws-ticket");
    if (request.caller.read_only && changes_state(request) && !ticket_request) {
      return refusal(core::ErrorCode::forbidden, "token '" + matched->name + "' may only read");
    }
    return std::nullopt;
  };
}

}  // namespace hrisim::http
