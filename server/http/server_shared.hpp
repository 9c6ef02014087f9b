#pragma once
// Private to the server (server.cpp, websocket_session.cpp): what its connections share — options,
// limits, the worker pool — and the seams between an HTTP connection and the WebSocket it becomes.
#include <atomic>
#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <variant>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/beast/core/tcp_stream.hpp>
#include <boost/beast/http/message.hpp>
#include <boost/beast/http/string_body.hpp>

#include "http/router.hpp"
#include "http/server.hpp"

namespace hrisim::http::serving {

namespace beast = boost::beast;
namespace bhttp = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;

class Connection;
class WebSocketSession;

/// State shared by the listener and every connection.
struct Shared {
  ServerOptions options;
  std::shared_ptr<const Router> router;
  net::thread_pool* workers = nullptr;  ///< runs deferred answers; owned by the server
  std::atomic<bool> stopping{false};
  std::mutex mutex;
  std::unordered_map<const Connection*, std::weak_ptr<Connection>> connections;
  std::unordered_map<const WebSocketSession*, std::weak_ptr<WebSocketSession>> websockets;
  std::size_t open = 0;  ///< admitted connections, HTTP and WebSocket
  std::unordered_map<std::string, std::size_t> open_per_client;  ///< by client address
};

/// Why Slot::take refuses when every connection of the server is taken.
inline constexpr const char* kAllTaken = "too many connections; retry later";

/// An admitted connection's place in the limits (all connections, and per client address), given back
/// when the connection — HTTP, then perhaps WebSocket — ends.
class Slot {
 public:
  /// Takes a place, or explains why there is none. `made_room`: a connection waiting for its header is
  /// being closed to make room, so the place is taken although its own is not given back yet.
  static std::variant<std::unique_ptr<Slot>, std::string> take(const std::shared_ptr<Shared>& shared, const std::string& client,
                                                               bool made_room = false) {
    std::lock_guard lock(shared->mutex);
    if (shared->open >= shared->options.max_connections && !made_room) return std::string(kAllTaken);
    std::size_t& mine = shared->open_per_client[client];
    if (mine >= shared->options.max_connections_per_client) {
      if (mine == 0) shared->open_per_client.erase(client);
      return "too many connections from " + client + " (at most " + std::to_string(shared->options.max_connections_per_client) + "); retry later";
    }
    ++mine;
    ++shared->open;
    return std::unique_ptr<Slot>(new Slot(shared, client));
  }
  ~Slot() {
    std::lock_guard lock(shared_->mutex);
    --shared_->open;
    if (--shared_->open_per_client[client_] == 0) shared_->open_per_client.erase(client_);
  }
  Slot(const Slot&) = delete;
  Slot& operator=(const Slot&) = delete;

 private:
  Slot(std::shared_ptr<Shared> shared, std::string client) : shared_(std::move(shared)), client_(std::move(client)) {}
  std::shared_ptr<Shared> shared_;
  std::string client_;
};

/// Brings a response to its answer on the worker pool (the caller is on a worker): deferred work runs
/// on this thread; a spread's parts are shared out over the pool, this thread taking the first, and the
/// worker that finishes the last part joins them. `done` gets the answer on that thread.
void answer_on_workers(net::thread_pool& workers, Response response, const std::string& where, std::function<void(Response)> done);

/// The connection's socket on a strand of the worker pool instead of the I/O threads; nothing when
/// the peer is already gone.
std::optional<tcp::socket> onto_workers(beast::tcp_stream& stream, net::thread_pool& workers);

/// Accepts the WebSocket `upgrade` on `socket` (already on a worker strand) and serves `peer` on it
/// until either side ends it; the socket keeps the HTTP connection's `slot`.
void start_websocket(tcp::socket&& socket, std::shared_ptr<WebSocketPeer> peer, std::shared_ptr<Shared> shared,
                     std::unique_ptr<Slot> slot, bhttp::request<bhttp::string_body> upgrade);

/// On shutdown: every open WebSocket gets a normal close ("going away").
void close_websockets(Shared& shared);

}  // namespace hrisim::http::serving
