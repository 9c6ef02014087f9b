#pragma once
// Requests and responses as plain values, and a router from (method, path pattern) to handlers.
// Free of Beast so that handlers and their tests compile without it.
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/caller.hpp"
#include "core/error.hpp"
#include "core/json_schema.hpp"

namespace hrisim::http {

/// Who sends a request, as the token guard found out.
using core::Caller;
using core::visible_to;

struct Request {
  Caller caller;
  std::string method;  ///< upper case, e.g. "GET"
  std::string path;    ///< percent-decoded path without the query
  std::string query;   ///< raw query string, without '?'
  std::map<std::string, std::string> headers;      ///< names in lower case
  std::map<std::string, std::string> path_params;  ///< values of {name} segments of the matched pattern
  std::string body;
  /// The body as JSON, checked against the route's schema in the request contract before the handler
  /// runs (RequestContract, Router::follow); null on a route without one.
  nlohmann::json checked_body;
};

struct Response {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;

  /// When set, the answer is what this returns, computed on the server's worker pool so that long
  /// work (stepping a simulation) never holds an I/O thread; the other fields are then ignored.
  std::function<Response()> deferred;

  /// When set, independent pieces of work that may run at once on the worker pool, and what makes the
  /// answer from their answers (in their order) once all are done; the other fields are then ignored.
  struct Spread {
    std::vector<std::function<Response()>> parts;
    std::function<Response(std::vector<Response>)> join;
  };
  std::shared_ptr<Spread> spread = nullptr;

  static Response json(int status, const nlohmann::json& value);
  /// {"error":{code,message,details}} with the error's HTTP status.
  static Response error(const core::Error& error);
  /// An answer computed later on the worker pool by `work` (which may throw core::Error).
  static Response later(std::function<Response()> work);
  /// An answer joined from parts computed at once on the worker pool (each may throw core::Error and
  /// then gives its error answer to the join).
  static Response spread_over(std::vector<std::function<Response()>> parts, std::function<Response(std::vector<Response>)> join);
  /// No answer: a WebSocket message that gets none (a pushed frame left out the same way).
  static Response nothing() { return Response{204, "", "", {}, {}}; }
  bool is_nothing() const { return status == 204 && body.empty() && !deferred && !spread; }
};

using Handler = std::function<Response(const Request&)>;

/// Content type of an answer sent as a binary WebSocket message.
inline constexpr const char* kBinaryContentType = "application/octet-stream";

/// A message a WebSocket client sent: text, or bytes it sent as a binary message.
struct WebSocketMessage {
  std::string data;
  bool binary = false;
};

/// One WebSocket peer: each message in gets at most one answer out, in order (a message is not read
/// before the previous one is answered). The answer's body is what is sent back — as a binary message
/// when its content type is kBinaryContentType; nothing for Response::nothing() — and it may be
/// deferred to the worker pool like an HTTP answer. A peer may also subscribe to frames pushed at a
/// rate; those are dropped, oldest first, when the client reads too slowly, answers never are.
class WebSocketPeer {
 public:
  virtual ~WebSocketPeer() = default;
  /// The subprotocol agreed at the upgrade (the answer's Sec-WebSocket-Protocol; see
  /// agree_subprotocol), empty for none.
  virtual std::string subprotocol() const { return {}; }
  /// Messages sent first, in order, as soon as the socket is open (a protocol's greeting), before any
  /// answer; never dropped. Each may be deferred like an answer.
  virtual std::vector<Response> on_open() { return {}; }
  virtual Response on_message(const WebSocketMessage& message) = 0;
  /// Pushed frames per second wanted now (0: none); read after every answer and every frame.
  virtual double push_rate() const { return 0.0; }
  /// The frames to push now, in order (none to skip this time): text, or binary by content type, and
  /// each may be deferred to the worker pool (rendering an image). Runs on the connection's I/O strand:
  /// it must not wait (e.g. skip when the session is busy). `dropped`: frames dropped so far on this
  /// socket.
  virtual std::vector<Response> push_frames(std::uint64_t dropped) {
    (void)dropped;
    return {};
  }
  /// Non-empty when the socket should end (what it served is gone): the server closes it with this
  /// reason. Read after every answer and about once a second.
  virtual std::string close_reason() const { return {}; }
};

/// The subprotocols a WebSocket upgrade offers (its Sec-WebSocket-Protocol, comma-separated), in the
/// client's order.
std::vector<std::string> offered_subprotocols(const Request& upgrade);
/// The first of `accepted` (the server's order of preference) that the upgrade offers. When it offers
/// none of them (or no subprotocol at all) the upgrade is refused: throws core::Error(bad_request),
/// a 400 naming what was offered and what is accepted.
std::string agree_subprotocol(const Request& upgrade, const std::vector<std::string>& accepted);

/// Makes the peer for an upgrade request (throws core::Error to refuse it: 404, 401, …).
using WebSocketFactory = std::function<std::shared_ptr<WebSocketPeer>(const Request&)>;

class RequestContract;

class Router {
 public:
  /// Routes added from now on are the operations of `contract`: each must be described there (else
  /// core::Error(internal), at start-up), and a route whose operation takes a JSON body gets it
  /// checked, every error at once with its pointer, into Request::checked_body before its handler runs.
  void follow(const RequestContract& contract) { contract_ = &contract; }

  /// Registers a handler; pattern segments written {name} match any one segment and land in path_params.
  void add(std::string method, std::string pattern, Handler handler);
  /// Runs before every request: a response from it is the answer (e.g. 401), nothing lets the request
  /// on; it may fill in the request's caller.
  void set_guard(std::function<std::optional<Response>(Request&)> guard) { guard_ = std::move(guard); }
  /// Answers requests no pattern matches (static files); without it they get 404.
  void set_fallback(Handler handler) { fallback_ = std::move(handler); }

  /// Registers a WebSocket endpoint (GET with Upgrade: websocket).
  void add_websocket(std::string pattern, WebSocketFactory factory);
  /// The peer for an upgrade request: guard first, then the endpoint; an HTTP error response when the
  /// upgrade is refused.
  std::variant<std::shared_ptr<WebSocketPeer>, Response> upgrade(Request request) const;

  /// Finds and runs the handler. Unknown path → 404, known path with another method → 405 with Allow;
  /// a core::Error thrown by a handler becomes its JSON error, any other exception a 500.
  Response dispatch(Request request) const;

 private:
  struct Route {
    std::string method;
    std::vector<std::string> segments;
    Handler handler;
    const core::JsonSchema* body = nullptr;  ///< the contract's schema of its JSON body, if it takes one
  };
  std::vector<Route> routes_;
  struct WebSocketRoute {
    std::vector<std::string> segments;
    WebSocketFactory factory;
  };
  std::vector<WebSocketRoute> websockets_;
  Handler fallback_;
  std::function<std::optional<Response>(Request&)> guard_;
  const RequestContract* contract_ = nullptr;
};

/// A route answered by a named member function of `Service` (what a group of routes shares: the
/// registry, the store), so each handler can be found by name and called alone.
template <typename Service>
struct NamedRoute {
  const char* method;
  const char* pattern;
  Response (Service::*handle)(const Request&) const;
};

/// Registers every route of `table`, each answered by its member function of `service`.
template <typename Service, std::size_t N>
void add_routes(Router& router, std::shared_ptr<const Service> service, const NamedRoute<Service> (&table)[N]) {
  for (const NamedRoute<Service>& route : table) {
    router.add(route.method, route.pattern, [service, handle = route.handle](const Request& request) { return ((*service).*handle)(request); });
  }
}

/// Runs a response's deferred work (and any work it hands on, a spread's parts one after another) until
/// the answer is there, on the calling thread: a core::Error becomes its JSON error, a JSON type error
/// a 400, anything else a 500 logged with `where`.
Response complete(Response response, const std::string& where);

/// Decodes %XX escapes (of a path, or a query's value); throws core::Error(bad_request) on a malformed
/// escape, an encoded NUL or what is not UTF-8 once decoded.
std::string percent_decode(std::string_view text);

}  // namespace hrisim::http
