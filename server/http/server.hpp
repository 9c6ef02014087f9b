#pragma once
// The HTTP server: accepts connections on a thread pool, reads requests within limits, hands them to
// a Router, and shuts down gracefully. Boost.Beast stays inside server.cpp and websocket_session.cpp.
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "http/router.hpp"

namespace hrisim::http {

/// Request header fields larger than this are answered 431.
inline constexpr std::size_t kDefaultHeaderLimit = 8 * 1024;
/// Request bodies larger than this are answered 413.
inline constexpr std::size_t kDefaultBodyLimit = 4 * 1024 * 1024;
/// A request's header must arrive within this time from the connection's start (or, kept alive, from
/// its previous answer), or the connection is closed: a client that trickles a header (slowloris)
/// holds its place for this long, not the read timeout. Ten seconds is ample for a header of at most
/// --header-limit bytes on any network a browser works over.
inline constexpr std::chrono::seconds kDefaultHeaderTimeout{10};
/// A request's body must arrive within this time from the end of its header, or the connection is closed.
inline constexpr std::chrono::seconds kDefaultReadTimeout{30};
/// Time allowed to send one response.
inline constexpr std::chrono::seconds kDefaultWriteTimeout{30};
/// Connections (WebSockets included) beyond this are answered 503 and closed, unless one of them is
/// waiting for a request's header: the one that has waited longest is then closed to make room.
inline constexpr std::size_t kDefaultMaxConnections = 256;
/// Connections (WebSockets included) one client address may hold; more are answered 503.
inline constexpr std::size_t kDefaultMaxConnectionsPerClient = 64;
/// Answers a WebSocket client may leave unread, by count and by bytes; past either the server closes
/// the socket with 1008 (policy violation).
inline constexpr std::size_t kDefaultMaxQueuedAnswers = 64;
inline constexpr std::size_t kDefaultMaxQueuedAnswerBytes = 64u << 20;
inline constexpr std::uint16_t kDefaultPort = 8080;

struct ServerOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = kDefaultPort;  ///< 0 picks a free port; see Server::port()
  std::size_t header_limit = kDefaultHeaderLimit;
  std::size_t body_limit = kDefaultBodyLimit;
  std::chrono::milliseconds header_timeout = kDefaultHeaderTimeout;
  std::chrono::milliseconds read_timeout = kDefaultReadTimeout;
  std::chrono::milliseconds write_timeout = kDefaultWriteTimeout;
  std::size_t max_connections = kDefaultMaxConnections;
  std::size_t max_connections_per_client = kDefaultMaxConnectionsPerClient;
  std::size_t max_queued_answers = kDefaultMaxQueuedAnswers;
  std::size_t max_queued_answer_bytes = kDefaultMaxQueuedAnswerBytes;
  unsigned threads = 0;  ///< 0 = one per core
  unsigned workers = 0;  ///< threads for deferred answers (simulation work); 0 = one per core
  bool log_requests = true;
};

class Server {
 public:
  /// Binds the listening socket (throws core::Error when the address is unusable).
  Server(ServerOptions options, std::shared_ptr<const Router> router);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  /// The bound port (useful with port 0).
  std::uint16_t port() const;

  /// Serves until SIGINT/SIGTERM or stop(): then stops accepting, lets requests in progress finish,
  /// closes idle connections and returns.
  void run();
  /// Thread-safe request to shut down as on a signal.
  void stop();

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hrisim::http
