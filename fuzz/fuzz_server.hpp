#pragma once
// The server the HTTP and WebSocket fuzz targets talk to, in process: the API router of `hrisim serve`
// over a scratch database and a run executor, once without tokens and once with owners' tokens.
#include <memory>
#include <string>
#include <string_view>

#include "http/router.hpp"

namespace hrisim::fuzz {

class Server {
 public:
  Server();
  ~Server();
  /// The answer to a request, deferred work done; runs it starts are cancelled at once (an input may
  /// ask for 100,000 episodes). A request with "Bearer" in it goes to the router with tokens.
  http::Response answer(http::Request request);
  /// The WebSocket of a live elevator session (with its HSR), made again when its session has ended.
  http::WebSocketPeer& socket();
  /// Runs deferred work until the answer is there.
  static http::Response settle(http::Response response);

 private:
  struct Parts;
  std::unique_ptr<Parts> parts_;
};

/// The one server of this process.
Server& server();

/// A request from text as it arrives: "METHOD TARGET" (target with its query), header lines up to an
/// empty line, then the body.
http::Request parse_request(std::string_view text);

/// Aborts (a finding) for an internal error: a bug the router caught. Every other answer is fine.
void check_reply(const http::Response& response);

}  // namespace hrisim::fuzz
