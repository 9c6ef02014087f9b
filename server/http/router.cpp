#include "http/router.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>

#include "core/text.hpp"
#include "http/request_contract.hpp"
#include "http/request_helpers.hpp"

namespace hrisim::http {
namespace {

std::vector<std::string> split_path(std::string_view path) {
  std::vector<std::string> segments;
  std::size_t start = 1;  // paths start with '/'
  while (start <= path.size()) {
    const std::size_t end = std::min(path.find('/', start), path.size());
    segments.emplace_back(path.substr(start, end - start));
    start = end + 1;
  }
  return segments;
}

std::optional<std::map<std::string, std::string>> match(const std::vector<std::string>& pattern,
                                                        const std::vector<std::string>& segments) {
  if (pattern.size() != segments.size()) return std::nullopt;
  std::map<std::string, std::string> params;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    const std::string& expected = pattern[i];
    if (expected.size() > 2 && expected.front() == '{' && expected.back() == '}') {
      if (segments[i].empty()) return std::nullopt;
      params[expected.substr(1, expected.size() - 2)] = segments[i];
    } else if (expected != segments[i]) {
      return std::nullopt;
    }
  }
  return params;
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

Response Response::json(int status, const nlohmann::json& value) {
  return Response{status, "application/json", core::json_text(value), {}, {}};
}

Response Response::error(const core::Error& error) { return json(core::http_status(error.code()), error.to_json()); }

Response Response::later(std::function<Response()> work) {
  Response response;
  response.deferred = std::move(work);
  return response;
}

Response Response::spread_over(std::vector<std::function<Response()>> parts, std::function<Response(std::vector<Response>)> join) {
  Response response;
  response.spread = std::make_shared<Spread>(Spread{std::move(parts), std::move(join)});
  return response;
}

std::vector<std::string> offered_subprotocols(const Request& upgrade) {
  std::vector<std::string> offered;
  const auto header = upgrade.headers.find("sec-websocket-protocol");
  if (header == upgrade.headers.end()) return offered;
  std::string_view rest = header->second;
  while (!rest.empty()) {
    const std::size_t comma = std::min(rest.find(','), rest.size());
    std::string_view item = rest.substr(0, comma);
    rest.remove_prefix(std::min(comma + 1, rest.size()));
    const std::size_t first = item.find_first_not_of(" \t");
    if (first == std::string_view::npos) continue;
    item = item.substr(first, item.find_last_not_of(" \t") - first + 1);
    offered.emplace_back(item);
  }
  return offered;
}

std::string agree_subprotocol(const Request& upgrade, const std::vector<std::string>& accepted) {
  const std::vector<std::string> offered = offered_subprotocols(upgrade);
  for (const std::string& mine : accepted) {
    if (std::find(offered.begin(), offered.end(), mine) != offered.end()) return mine;
  }
  throw core::Error(core::ErrorCode::bad_request,
                    offered.empty() ? "this WebSocket needs a subprotocol (Sec-WebSocket-Protocol): " + core::join(accepted, " or ")
                                    : "none of the subprotocols offered (" + core::join(offered) + ") is accepted here: " +
                                          core::join(accepted, " or "),
                    {{"offered", offered}, {"accepted", accepted}});
}

void Router::add(std::string method, std::string pattern, Handler handler) {
  const core::JsonSchema* body = nullptr;
  if (contract_ != nullptr) {
    const RequestContract::Operation* operation = contract_->operation(method, pattern);
    if (operation == nullptr) throw core::Error(core::ErrorCode::internal, method + " " + pattern + " is not described in api/openapi.yaml");
    body = operation->body;
  }
  routes_.push_back({std::move(method), split_path(pattern), std::move(handler), body});
}

void Router::add_websocket(std::string pattern, WebSocketFactory factory) {
  websockets_.push_back({split_path(pattern), std::move(factory)});
}

std::variant<std::shared_ptr<WebSocketPeer>, Response> Router::upgrade(Request request) const {
  try {
    if (guard_) {
      if (auto refused = guard_(request)) return *refused;
    }
    const std::vector<std::string> segments = split_path(request.path);
    for (const WebSocketRoute& route : websockets_) {
      auto params = match(route.segments, segments);
      if (!params) continue;
      request.path_params = std::move(*params);
      return route.factory(request);
    }
    return Response::error(core::Error(core::ErrorCode::not_found, "no WebSocket endpoint at " + request.path, {{"path", request.path}}));
  } catch (const core::Error& e) {
    return Response::error(e);
  }
}

Response Router::dispatch(Request request) const {
  try {
    if (guard_) {
      if (auto refused = guard_(request)) return *refused;
    }
    const std::vector<std::string> segments = split_path(request.path);
    std::string allowed;
    for (const Route& route : routes_) {
      auto params = match(route.segments, segments);
      if (!params) continue;
      if (route.method == request.method || (route.method == "GET" && request.method == "HEAD")) {
        request.path_params = std::move(*params);
        if (route.body != nullptr) {
          request.checked_body = json_object_body(request);
          check_against(*route.body, request.checked_body);
        }
        return route.handler(request);
      }
      allowed += (allowed.empty() ? "" : ", ") + route.method;
    }
    if (!allowed.empty()) {
      Response response = Response::error(core::Error(
          core::ErrorCode::method_not_allowed, request.method + " is not allowed on " + request.path,
          {{"allowed", allowed}}));
      response.headers.emplace_back("Allow", allowed);
      return response;
    }
    if (fallback_) return fallback_(request);
    return Response::error(core::Error(core::ErrorCode::not_found, "no resource at " + request.path,
                                       {{"path", request.path}}));
  } catch (const core::Error& e) {
    return Response::error(e);
  } catch (const nlohmann::json::exception& e) {
    return Response::error(core::Error(core::ErrorCode::bad_request, std::string("invalid JSON: ") + e.what()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hrisim: internal error on %s %s: %s\n", request.method.c_str(), request.path.c_str(),
                 e.what());
    return Response::error(core::Error(core::ErrorCode::internal, "internal error"));
  }
}

Response complete(Response response, const std::string& where) {
  try {
    // One after another here; the server shares a spread's parts out over its workers instead.
    while (response.deferred || response.spread) {
      if (response.deferred) {
        response = response.deferred();
        continue;
      }
      std::vector<Response> answers;
      for (auto& part : response.spread->parts) answers.push_back(complete(Response::later(std::move(part)), where));
      response = response.spread->join(std::move(answers));
    }
    return response;
  } catch (const core::Error& e) {
    return Response::error(e);
  } catch (const nlohmann::json::exception& e) {
    return Response::error(core::Error(core::ErrorCode::bad_request, std::string("invalid JSON: ") + e.what()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "hrisim: internal error on %s: %s\n", where.c_str(), e.what());
    return Response::error(core::Error(core::ErrorCode::internal, "internal error"));
  }
}

std::string percent_decode(std::string_view text) {
  std::string decoded;
  decoded.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '%') {
      decoded += text[i];
      continue;
    }
    const int high = i + 2 < text.size() ? hex_value(text[i + 1]) : -1;
    const int low = i + 2 < text.size() ? hex_value(text[i + 2]) : -1;
    if (high < 0 || low < 0) {
      throw core::Error(core::ErrorCode::bad_request, "malformed percent escape in the request's path or query",
                        {{"offset", i}});
    }
    const char c = static_cast<char>(high * 16 + low);
    if (c == '\0') throw core::Error(core::ErrorCode::bad_request, "encoded NUL in the request's path or query", {{"offset", i}});
    decoded += c;
    i += 2;
  }
  if (const auto bad = core::invalid_utf8_offset(decoded)) {
    throw core::Error(core::ErrorCode::bad_request, "the request's path or query is not UTF-8 once decoded", {{"offset", *bad}});
  }
  return decoded;
}

}  // namespace hrisim::http
