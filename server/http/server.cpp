#include "http/server.hpp"

#include <algorithm>
#include <atomic>

#include <boost/asio/dispatch.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket/rfc6455.hpp>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <optional>
#include <thread>
#include <vector>

#include "core/build_info.hpp"
#include "core/text.hpp"
#include "http/server_shared.hpp"

namespace hrisim::http {
namespace serving {

/// After an error reply, unread request bytes are drained this long before closing, so the client
/// reads the reply instead of a connection reset.
constexpr std::chrono::seconds kLingerTimeout{2};


/// How long the listener waits before accepting again after a failed accept (no descriptors left).
constexpr std::chrono::milliseconds kAcceptRetryDelay{100};
/// A failed accept is logged at most this often.
constexpr std::chrono::seconds kAcceptErrorLogInterval{10};

/// Brings a response to its answer on the worker pool (the caller is on a worker): deferred work runs
/// on this thread; a spread's parts are shared out over the pool, this thread taking the first, and the
/// worker that finishes the last part joins them. `done` gets the answer on that thread.
void answer_on_workers(net::thread_pool& workers, Response response, const std::string& where, std::function<void(Response)> done) {
  if (!response.spread || response.spread->parts.empty()) return done(complete(std::move(response), where));
  struct Gathering {
    std::shared_ptr<Response::Spread> spread;
    std::vector<Response> answers;
    std::atomic<std::size_t> left;
    std::string where;
    std::function<void(Response)> done;
  };
  const std::size_t parts = response.spread->parts.size();
  auto gathering = std::make_shared<Gathering>();
  gathering->spread = std::move(response.spread);
  gathering->answers.resize(parts);
  gathering->left = parts;
  gathering->where = where;
  gathering->done = std::move(done);
  const auto run = [gathering](std::size_t part) {
    gathering->answers[part] = complete(Response::later(std::move(gathering->spread->parts[part])), gathering->where);
    if (gathering->left.fetch_sub(1) != 1) return;
    gathering->done(complete(Response::later([gathering] { return gathering->spread->join(std::move(gathering->answers)); }), gathering->where));
  };
  for (std::size_t part = 1; part < parts; ++part) net::post(workers, [run, part] { run(part); });
  run(0);
}

/// The connection's socket on a strand of the worker pool instead of the I/O threads; nothing when
/// the peer is already gone.
std::optional<tcp::socket> onto_workers(beast::tcp_stream& stream, net::thread_pool& workers) {
  stream.expires_never();
  tcp::socket on_io = stream.release_socket();
  beast::error_code ec;
  const auto protocol = on_io.local_endpoint(ec).protocol();
  if (ec) return std::nullopt;
  return tcp::socket(net::make_strand(workers.get_executor()), protocol, on_io.release());
}


namespace {
std::string utc_timestamp() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm parts{};
  gmtime_r(&now, &parts);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &parts);
  return text;
}
}  // namespace

class Connection : public std::enable_shared_from_this<Connection> {
 public:
  Connection(tcp::socket&& socket, std::shared_ptr<Shared> shared, std::unique_ptr<Slot> slot, bool on_workers = false)
      : stream_(std::move(socket)), shared_(std::move(shared)), slot_(std::move(slot)), on_workers_(on_workers) {}

  ~Connection() {
    std::lock_guard lock(shared_->mutex);
    shared_->connections.erase(this);
  }

  void start() {
    net::dispatch(stream_.get_executor(), beast::bind_front_handler(&Connection::read_request, shared_from_this()));
  }

  /// Answers 503 (too many connections) and closes.
  void reject_busy(const std::string& why) {
    net::dispatch(stream_.get_executor(), [self = shared_from_this(), why] {
      self->busy_ = true;
      Response response = Response::error(core::Error(core::ErrorCode::unavailable, why));
      response.headers.emplace_back("Retry-After", "1");
      self->send(std::move(response), 11, false, false);
    });
  }

  /// Since when (steady clock, ns) the connection has waited for a request's header; 0 when it is not
  /// waiting, -1 once chosen to make room (see make_room).
  std::int64_t waiting_since() const { return waiting_since_; }
  /// Chooses this connection to make room, unless its header arrived meanwhile.
  bool claim_for_eviction(std::int64_t since) { return waiting_since_.compare_exchange_strong(since, -1); }
  /// Closes the connection chosen to make room, unless its header has arrived meanwhile.
  void evict() {
    net::dispatch(stream_.get_executor(), [self = shared_from_this()] {
      if (self->waiting_since_ == -1) self->close();
    });
  }

  /// On shutdown: a connection waiting for a request is closed; one serving a request finishes it first.
  void shutdown_if_idle() {
    net::dispatch(stream_.get_executor(), [self = shared_from_this()] {
      if (!self->busy_) self->close();
    });
  }

 private:
  void read_request() {
    parser_.emplace();
    parser_->header_limit(static_cast<std::uint32_t>(shared_->options.header_limit));
    parser_->body_limit(shared_->options.body_limit);
    waiting_since_ = std::chrono::steady_clock::now().time_since_epoch().count();
    stream_.expires_after(std::min(shared_->options.header_timeout, shared_->options.read_timeout));
    bhttp::async_read_header(stream_, buffer_, *parser_,
                             beast::bind_front_handler(&Connection::on_header, shared_from_this()));
  }

  /// Clients that announce a body with "Expect: 100-continue" (curl does above 1 KiB) wait for an
  /// interim 100 before sending it; oversized bodies were already refused when the header was parsed.
  void on_header(beast::error_code ec, std::size_t bytes) {
    waiting_since_ = 0;
    if (ec || parser_->is_done()) return on_read(ec, bytes);
    const auto& header = parser_->get();
    if (!beast::iequals(header[bhttp::field::expect], "100-continue")) return read_body();
    auto interim = std::make_shared<bhttp::response<bhttp::empty_body>>(bhttp::status::continue_, header.version());
    bhttp::async_write(stream_, *interim, [self = shared_from_this(), interim](beast::error_code write_ec, std::size_t) {
      if (write_ec) return self->close();
      self->read_body();
    });
  }

  void read_body() {
    stream_.expires_after(shared_->options.read_timeout);
    bhttp::async_read(stream_, buffer_, *parser_, beast::bind_front_handler(&Connection::on_read, shared_from_this()));
  }

  void on_read(beast::error_code ec, std::size_t) {
    if (ec == bhttp::error::end_of_stream || ec == beast::error::timeout || ec == net::error::operation_aborted) {
      return close();
    }
    busy_ = true;
    const unsigned version = parser_->get().version() == 10 ? 10 : 11;
    if (ec == bhttp::error::header_limit) {
      return send(Response::error(core::Error(core::ErrorCode::headers_too_large,
                                              "request header fields exceed the limit",
                                              {{"limit_bytes", shared_->options.header_limit}})),
                  version, false, false);
    }
    if (ec == bhttp::error::body_limit) {
      return send(Response::error(core::Error(core::ErrorCode::payload_too_large, "request body exceeds the limit",
                                              {{"limit_bytes", shared_->options.body_limit}})),
                  version, false, false);
    }
    if (ec) {
      // Socket errors and a request cut short leave nobody to answer; malformed HTTP gets a 400.
      const bool http_error = ec.category() == bhttp::make_error_code(bhttp::error::bad_method).category();
      if (!http_error || ec == bhttp::error::partial_message) return close();
      return send(Response::error(core::Error(core::ErrorCode::bad_request, "malformed HTTP request: " + ec.message())),
                  version, false, false);
    }
    handle(parser_->release());
  }

  /// Method, query and headers (names in lower case) of a request; the path is the caller's.
  static Request request_of(const bhttp::request<bhttp::string_body>& message) {
    Request request;
    request.method = std::string(message.method_string());
    const std::string_view target(message.target().data(), message.target().size());
    const std::size_t query_start = target.find('?');
    request.query = query_start == std::string_view::npos ? "" : std::string(target.substr(query_start + 1));
    for (const auto& field : message) {
      request.headers[core::lower_case(std::string(field.name_string()))] = std::string(field.value());
    }
    return request;
  }

  /// What the reply to a request needs to know about it.
  struct Answered {
    std::string method, target;
    std::chrono::steady_clock::time_point started;
    unsigned version;
    bool keep_alive, head;
  };

  void handle(bhttp::request<bhttp::string_body> message) {
    if (beast::websocket::is_upgrade(message)) return upgrade(std::move(message));
    const auto started = std::chrono::steady_clock::now();
    Request request = request_of(message);
    const std::string_view target(message.target().data(), message.target().size());
    const std::size_t query_start = target.find('?');
    request.body = std::move(message.body());
    const bool head = message.method() == bhttp::verb::head;
    const bool keep_alive = message.keep_alive() && !shared_->stopping;

    Response response;
    try {
      if (target.empty() || target.front() != '/') {
        throw core::Error(core::ErrorCode::bad_request, "request target must be an absolute path");
      }
      request.path = percent_decode(target.substr(0, query_start));
      response = shared_->router->dispatch(std::move(request));
    } catch (const core::Error& e) {
      response = Response::error(e);
    } catch (const std::exception& e) {
      // The router catches what handlers throw; this is the last line before the process would end.
      std::fprintf(stderr, "hrisim: internal error on a request: %s\n", e.what());
      response = Response::error(core::Error(core::ErrorCode::internal, "internal error"));
    }
    Answered answered{std::string(message.method_string()), std::string(target), started, message.version(), keep_alive, head};
    if (!response.deferred && !response.spread) return finish(std::move(response), answered);
    if (on_workers_) return answer_here(std::move(response), std::move(answered));
    move_to_workers(std::move(response), std::move(answered));
  }

  /// Work for a connection on the worker pool: it runs on this thread (a spread's parts over the pool)
  /// and the answer goes out from this connection's strand.
  void answer_here(Response response, Answered answered) {
    const std::string where = answered.method + " " + answered.target;
    answer_on_workers(*shared_->workers, std::move(response), where, [self = shared_from_this(), answered = std::move(answered)](Response result) {
      net::dispatch(self->stream_.get_executor(), [self, result = std::move(result), answered]() mutable { self->finish(std::move(result), answered); });
    });
  }

  /// A connection's first request with work (a step) moves it from the I/O threads to a strand of the
  /// worker pool, as a WebSocket moves at its upgrade: that request and the connection's next ones are
  /// read, worked on and answered on one worker thread, with no hand-over to a worker and back, while
  /// connections that only fetch files stay on the I/O threads.
  void move_to_workers(Response response, Answered answered) {
    std::optional<tcp::socket> socket = onto_workers(stream_, *shared_->workers);
    if (!socket) return;
    auto moved = std::make_shared<Connection>(std::move(*socket), shared_, std::move(slot_), true);
    moved->buffer_ = std::move(buffer_);  // a request the client sent behind this one
    moved->busy_ = true;
    {
      std::lock_guard lock(shared_->mutex);
      shared_->connections.emplace(moved.get(), moved);
    }
    net::dispatch(moved->stream_.get_executor(), [moved, response = std::move(response), answered = std::move(answered)]() mutable {
      moved->answer_here(std::move(response), std::move(answered));
    });
  }

  /// A WebSocket upgrade: the router finds the endpoint (or answers with an HTTP error), and the
  /// socket moves on to a WebSocket session.
  void upgrade(bhttp::request<bhttp::string_body> message) {
    Request request = request_of(message);
    const std::string_view target(message.target().data(), message.target().size());
    request.path = std::string(target.substr(0, target.find('?')));
    auto outcome = shared_->router->upgrade(std::move(request));
    if (auto* refused = std::get_if<Response>(&outcome)) return send(std::move(*refused), message.version(), false, false);
    // The socket moves from the I/O threads to a strand of the worker pool (see WebSocketSession).
    std::optional<tcp::socket> socket = onto_workers(stream_, *shared_->workers);
    if (!socket) return;
    start_websocket(std::move(*socket), std::get<std::shared_ptr<WebSocketPeer>>(outcome), shared_, std::move(slot_), std::move(message));
  }

  void finish(Response response, const Answered& answered) {
    if (shared_->options.log_requests) {
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - answered.started).count();
      std::fprintf(stderr, "%s %s %s %d %.2f ms\n", utc_timestamp().c_str(), answered.method.c_str(), answered.target.c_str(),
                   response.status, ms);
    }
    send(std::move(response), answered.version, answered.keep_alive, answered.head);
  }

  void send(Response response, unsigned version, bool keep_alive, bool head) {
    auto message = std::make_shared<bhttp::response<bhttp::string_body>>(
        static_cast<bhttp::status>(response.status), version);
    message->set(bhttp::field::server, std::string("hrisim/") + core::version());
    // A 204 or 304 has no body, so no type either; nor has an answer that names none (a 416).
    if (response.status != 204 && response.status != 304 && !response.content_type.empty()) {
      message->set(bhttp::field::content_type, response.content_type);
    }
    message->set("X-Content-Type-Options", "nosniff");
    for (const auto& [name, value] : response.headers) message->set(name, value);
    message->keep_alive(keep_alive);
    if (head) {
      message->content_length(response.body.size());
    } else {
      message->body() = std::move(response.body);
      message->prepare_payload();
    }
    stream_.expires_after(shared_->options.write_timeout);
    bhttp::async_write(stream_, *message,
                       [self = shared_from_this(), message, keep_alive](beast::error_code ec, std::size_t) {
                         self->on_write(ec, keep_alive);
                       });
  }

  void on_write(beast::error_code ec, bool keep_alive) {
    busy_ = false;
    if (ec) return close();
    if (!keep_alive || shared_->stopping) return linger_close();
    read_request();
  }

  /// Half-closes, then discards whatever the client still sends until it closes or the linger time ends.
  void linger_close() {
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
    stream_.expires_after(kLingerTimeout);
    drain();
  }

  void drain() {
    stream_.async_read_some(net::buffer(discard_), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->close();
      self->drain();
    });
  }

  void close() {
    beast::error_code ignored;
    stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
    stream_.close();
  }

  beast::tcp_stream stream_;
  std::shared_ptr<Shared> shared_;
  std::unique_ptr<Slot> slot_;  ///< null for a connection turned away; moves on to its WebSocket
  beast::flat_buffer buffer_;
  std::optional<bhttp::request_parser<bhttp::string_body>> parser_;
  std::array<char, 4096> discard_{};
  bool busy_ = false;  ///< a request is being answered (touched only on the strand)
  std::atomic<std::int64_t> waiting_since_{0};  ///< see waiting_since()
  bool on_workers_;    ///< on a strand of the worker pool (see move_to_workers)
};

/// When every connection is taken, the one that has waited longest for a request's header (a client
/// trickling it, or an idle kept-alive one) is closed to make room: clients that send whole requests
/// are served however many slow ones hold places. False when no connection is waiting.
bool make_room(Shared& shared) {
  std::shared_ptr<Connection> victim;  // released after the lock: its destructor takes the lock
  {
    std::lock_guard lock(shared.mutex);
    // A connection in the table is alive at least until this lock is released (its destructor
    // erases it under the lock), so its members may be read.
    const Connection* oldest = nullptr;
    std::int64_t oldest_since = 0;
    for (const auto& [connection, unused] : shared.connections) {
      const std::int64_t since = connection->waiting_since();
      if (since > 0 && (!oldest || since < oldest_since)) {
        oldest = connection;
        oldest_since = since;
      }
    }
    // The table's keys are const; the claim changes only the connection's own atomic mark.
    if (!oldest || !const_cast<Connection*>(oldest)->claim_for_eviction(oldest_since)) return false;
    victim = shared.connections.at(oldest).lock();
  }
  if (victim) victim->evict();
  return true;
}

class Listener : public std::enable_shared_from_this<Listener> {
 public:
  Listener(net::io_context& io, const tcp::endpoint& endpoint, std::shared_ptr<Shared> shared)
      : io_(io), acceptor_(net::make_strand(io)), shared_(std::move(shared)) {
    beast::error_code ec;
    acceptor_.open(endpoint.protocol(), ec);
    if (!ec) acceptor_.set_option(net::socket_base::reuse_address(true), ec);
    if (!ec) acceptor_.bind(endpoint, ec);
    if (!ec) acceptor_.listen(net::socket_base::max_listen_connections, ec);
    if (ec) {
      throw core::Error(core::ErrorCode::unavailable,
                        "cannot listen on " + endpoint.address().to_string() + ":" + std::to_string(endpoint.port()) +
                            ": " + ec.message(),
                        {{"host", endpoint.address().to_string()}, {"port", endpoint.port()}});
    }
  }

  std::uint16_t port() const { return acceptor_.local_endpoint().port(); }

  void accept() {
    acceptor_.async_accept(net::make_strand(io_), beast::bind_front_handler(&Listener::on_accept, shared_from_this()));
  }

  void close() {
    net::dispatch(acceptor_.get_executor(), [self = shared_from_this()] {
      beast::error_code ignored;
      self->acceptor_.close(ignored);
      self->retry_timer_.cancel();
    });
  }

 private:
  void on_accept(beast::error_code ec, tcp::socket socket) {
    if (ec == net::error::operation_aborted || !acceptor_.is_open()) return;
    if (ec) {
      // Out of descriptors, typically: accepting again at once would fail again at once, so wait a
      // little (connections close meanwhile) and say so now and then, not at every attempt.
      ++failed_accepts_;
      const auto now = std::chrono::steady_clock::now();
      if (now - last_accept_error_log_ >= kAcceptErrorLogInterval) {
        std::fprintf(stderr, "hrisim: accept failed: %s (%llu failed accepts so far; retrying every %lld ms)\n", ec.message().c_str(),
                     static_cast<unsigned long long>(failed_accepts_), static_cast<long long>(kAcceptRetryDelay.count()));
        last_accept_error_log_ = now;
      }
      retry_timer_.expires_after(kAcceptRetryDelay);
      retry_timer_.async_wait([self = shared_from_this()](beast::error_code timer_ec) {
        if (!timer_ec) self->accept();
      });
      return;
    }
    if (shared_->stopping) return;
    // Answers go out at once: with Nagle's algorithm the tail of a large answer (an image) waits for
    // the client's delayed acknowledgement, 40 ms on Linux.
    beast::error_code ignored;
    socket.set_option(tcp::no_delay(true), ignored);
    const auto remote = socket.remote_endpoint(ignored);
    const std::string client = ignored ? std::string("unknown") : remote.address().to_string();
    auto slot = Slot::take(shared_, client);
    if (const auto* why = std::get_if<std::string>(&slot); why && *why == kAllTaken && make_room(*shared_)) {
      slot = Slot::take(shared_, client, true);
    }
    if (auto* why = std::get_if<std::string>(&slot)) {
      std::make_shared<Connection>(std::move(socket), shared_, nullptr)->reject_busy(*why);
    } else {
      auto connection = std::make_shared<Connection>(std::move(socket), shared_, std::move(std::get<std::unique_ptr<Slot>>(slot)));
      {
        std::lock_guard lock(shared_->mutex);
        shared_->connections.emplace(connection.get(), connection);
      }
      connection->start();
    }
    accept();
  }

  net::io_context& io_;
  tcp::acceptor acceptor_;
  std::shared_ptr<Shared> shared_;
  net::steady_timer retry_timer_{acceptor_.get_executor()};
  std::uint64_t failed_accepts_ = 0;
  std::chrono::steady_clock::time_point last_accept_error_log_{};
};

}  // namespace serving

using namespace serving;

class Server::Impl {
 public:
  Impl(ServerOptions options, std::shared_ptr<const Router> router)
      : threads_(options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency())),
        io_(static_cast<int>(threads_)),
        workers_(options.workers ? options.workers : std::max(1u, std::thread::hardware_concurrency())),
        signals_(io_, SIGINT, SIGTERM),
        shared_(std::make_shared<Shared>()) {
    shared_->router = std::move(router);
    shared_->workers = &workers_;
    // The pool's event loop (epoll and its descriptors) comes with its first I/O object: made now, so
    // the server holds as many descriptors from its start as after its first WebSocket.
    net::steady_timer{workers_.get_executor()};
    beast::error_code ec;
    const auto address = net::ip::make_address(options.host, ec);
    if (ec) {
      throw core::Error(core::ErrorCode::bad_request, "host " + options.host + " is not an IP address",
                        {{"host", options.host}});
    }
    listener_ = std::make_shared<Listener>(io_, tcp::endpoint(address, options.port), shared_);
    shared_->options = std::move(options);
  }

  std::uint16_t port() const { return listener_->port(); }

  void run() {
    signals_.async_wait([this](beast::error_code ec, int) {
      if (!ec) begin_shutdown();
    });
    listener_->accept();
    std::vector<std::thread> pool;
    for (unsigned i = 1; i < threads_; ++i) pool.emplace_back([this] { io_.run(); });
    io_.run();
    for (std::thread& thread : pool) thread.join();
    workers_.join();
  }

  void stop() {
    net::post(io_, [this] { begin_shutdown(); });
  }

 private:
  void begin_shutdown() {
    if (shared_->stopping.exchange(true)) return;
    beast::error_code ignored;
    signals_.cancel(ignored);
    listener_->close();
    std::vector<std::shared_ptr<Connection>> live;
    {
      std::lock_guard lock(shared_->mutex);
      for (const auto& [key, weak] : shared_->connections) {
        if (auto connection = weak.lock()) live.push_back(std::move(connection));
      }
    }
    for (const auto& connection : live) connection->shutdown_if_idle();
    serving::close_websockets(*shared_);
  }

  unsigned threads_;
  net::io_context io_;
  net::thread_pool workers_;
  net::signal_set signals_;
  std::shared_ptr<Shared> shared_;
  std::shared_ptr<Listener> listener_;
};

Server::Server(ServerOptions options, std::shared_ptr<const Router> router)
    : impl_(std::make_unique<Impl>(std::move(options), std::move(router))) {}

Server::~Server() = default;

std::uint16_t Server::port() const { return impl_->port(); }

void Server::run() { impl_->run(); }

void Server::stop() { impl_->stop(); }

}  // namespace hrisim::http
