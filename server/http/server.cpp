#include "http/server.hpp"

#include <algorithm>
#include <atomic>

#include <boost/asio/dispatch.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/strand.hpp>
#include <boost/asio/thread_pool.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <deque>
#include <cctype>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <mutex>
#include <set>
#include <optional>
#include <variant>
#include <thread>
#include <unordered_map>
#include <vector>

#include "core/build_info.hpp"
#include "core/text.hpp"

namespace hrisim::http {
namespace {

namespace beast = boost::beast;
namespace bhttp = beast::http;
namespace net = boost::asio;
using tcp = net::ip::tcp;

/// After an error reply, unread request bytes are drained this long before closing, so the client
/// reads the reply instead of a connection reset.
constexpr std::chrono::seconds kLingerTimeout{2};

class Connection;
class WebSocketSession;

/// Largest WebSocket message accepted; bigger ones close the connection (code 1009).
constexpr std::size_t kMaxWebSocketMessage = 1 << 20;
/// Pushes (a state frame with its image, if any) waiting behind the write in flight at most; the
/// oldest is dropped for a newer one.
constexpr std::size_t kMaxQueuedFrames = 4;

/// How long the listener waits before accepting again after a failed accept (no descriptors left).
constexpr std::chrono::milliseconds kAcceptRetryDelay{100};
/// A failed accept is logged at most this often.
constexpr std::chrono::seconds kAcceptErrorLogInterval{10};
/// How often a WebSocket asks its peer whether it should end.
constexpr std::chrono::seconds kWebSocketWatchInterval{1};
/// After a close frame the server sent, the socket is cut this long later if the close has not completed
/// (shorter when the server shuts down: it waits for every socket).
constexpr std::chrono::seconds kWebSocketCloseGrace{5};
constexpr std::chrono::milliseconds kWebSocketShutdownGrace{500};

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

/// An admitted connection's place in the limits (all connections, and per client address), given back
/// when the connection — HTTP, then perhaps WebSocket — ends.
class Slot {
 public:
  /// Takes a place, or explains why there is none.
  static std::variant<std::unique_ptr<Slot>, std::string> take(const std::shared_ptr<Shared>& shared, const std::string& client) {
    std::lock_guard lock(shared->mutex);
    if (shared->open >= shared->options.max_connections) return std::string("too many connections; retry later");
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

/// A WebSocket connection: one message read, answered, its answer queued, then the next read — so
/// answers come in the order of the messages. The socket lives on a strand of the worker pool, so a
/// message is read, answered (a step run) and its answer written on one worker thread, with no hand-over
/// between threads; HTTP connections, on the I/O threads, are never held up by it. Writes go out one at
/// a time from a queue, each message as one frame; pushed frames join the queue at the peer's rate, and
/// a slow reader loses the oldest queued frames, never answers. Beast's suggested server timeouts ping
/// idle peers and drop dead ones.
class WebSocketSession : public std::enable_shared_from_this<WebSocketSession> {
 public:
  WebSocketSession(tcp::socket&& socket, std::shared_ptr<WebSocketPeer> peer, std::shared_ptr<Shared> shared, std::unique_ptr<Slot> slot)
      : ws_(std::move(socket)), peer_(std::move(peer)), shared_(std::move(shared)), slot_(std::move(slot)) {}

  ~WebSocketSession() {
    std::lock_guard lock(shared_->mutex);
    shared_->websockets.erase(this);
  }

  void start(bhttp::request<bhttp::string_body> upgrade) {
    {
      std::lock_guard lock(shared_->mutex);
      shared_->websockets.emplace(this, weak_from_this());
    }
    ws_.set_option(beast::websocket::stream_base::timeout::suggested(beast::role_type::server));
    ws_.read_message_max(kMaxWebSocketMessage);
    // Whole messages as one frame each: Beast's default cuts them into 4 KB frames, which costs a
    // 512 KiB camera frame 128 headers and as many writes.
    ws_.auto_fragment(false);
    ws_.text(true);
    ws_.async_accept(upgrade, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return;
      self->read();
      self->watch();
    });
  }

  /// On shutdown: a normal close.
  void close() {
    net::dispatch(ws_.get_executor(), [self = shared_from_this()] { self->end(beast::websocket::close_code::going_away, ""); });
  }

 private:
  void read() {
    if (closing_) return;
    if (const std::string reason = peer_->close_reason(); !reason.empty()) return end(beast::websocket::close_code::normal, reason);
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return;  // closed, timed out or too big: Beast has told the peer
      std::string text = beast::buffers_to_string(self->buffer_.data());
      self->buffer_.consume(self->buffer_.size());
      self->answer(std::move(text));
    });
  }

  void answer(std::string text) {
    Response response;
    try {
      response = peer_->on_message(text);
    } catch (const core::Error& e) {
      response = Response::error(e);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hrisim: internal error on a WebSocket message: %s\n", e.what());
      response = Response::error(core::Error(core::ErrorCode::internal, "internal error"));
    }
    // Already on a worker: deferred work runs here, and the answer is sent from this strand.
    answer_on_workers(*shared_->workers, std::move(response), "a WebSocket", [self = shared_from_this()](Response answer) {
      net::dispatch(self->ws_.get_executor(), [self, answer = std::move(answer)]() mutable {
        self->send({std::move(answer.body), answer.content_type == kBinaryContentType, false});
        self->schedule_push();
        self->read();
      });
    });
  }

  struct Outgoing {
    std::string data;
    bool binary = false;
    bool droppable = false;  ///< a pushed frame, not an answer
    std::uint64_t group = 0;  ///< pushed frames pushed together (a state frame and its image) go together
  };

  void send(Outgoing message) {
    if (closing_) return;
    if (!message.droppable && over_answer_limit(message.data.size())) {
      return end(beast::websocket::close_code::policy_error,
                 "more than " + std::to_string(shared_->options.max_queued_answers) + " answers or " +
                     std::to_string(shared_->options.max_queued_answer_bytes) + " bytes unread");
    }
    if (message.droppable && (outbox_.empty() || outbox_.back().group != message.group)) {
      // The first message may be in flight; of the rest, the oldest push makes room, all its frames
      // at once — but not one whose first frame is being written.
      const auto queued = outbox_.begin() + (outbox_.empty() ? 0 : 1);
      const std::uint64_t in_flight = outbox_.empty() ? 0 : outbox_.front().group;
      std::set<std::uint64_t> groups;
      for (auto m = queued; m != outbox_.end(); ++m) {
        if (m->droppable) groups.insert(m->group);
      }
      if (groups.size() >= kMaxQueuedFrames) {
        const auto oldest = std::find_if(groups.begin(), groups.end(), [&](std::uint64_t g) { return g != in_flight; });
        if (oldest != groups.end()) {
          const std::uint64_t dropped_group = *oldest;
          outbox_.erase(std::remove_if(queued, outbox_.end(), [&](const Outgoing& m) { return m.droppable && m.group == dropped_group; }),
                        outbox_.end());
          ++dropped_;
        }
      }
    }
    outbox_.push_back(std::move(message));
    if (outbox_.size() == 1) write_next();
  }

  /// True when one more answer of `bytes` would pass the limits of what a client may leave unread.
  bool over_answer_limit(std::size_t bytes) const {
    std::size_t answers = 1;
    for (const Outgoing& queued : outbox_) {
      if (queued.droppable) continue;
      ++answers;
      bytes += queued.data.size();
    }
    return answers > shared_->options.max_queued_answers || bytes > shared_->options.max_queued_answer_bytes;
  }

  void write_next() {
    ws_.binary(outbox_.front().binary);
    ws_.async_write(net::buffer(outbox_.front().data), [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return;
      self->outbox_.pop_front();
      if (self->outbox_.empty()) {
        if (self->closing_) self->send_close();
        return;
      }
      self->write_next();
    });
  }

  /// Ends the socket: what waits behind the write in flight is dropped, a close frame with `code` and
  /// `reason` follows that write, and the connection is cut if the peer has not completed the close
  /// kWebSocketCloseGrace later (a client that reads nothing never will).
  void end(beast::websocket::close_code code, const std::string& reason) {
    if (closing_) return;
    closing_ = true;
    close_reason_ = {code, beast::websocket::reason_string(reason.substr(0, 120))};
    push_timer_.cancel();
    watch_timer_.cancel();
    if (outbox_.size() > 1) outbox_.erase(outbox_.begin() + 1, outbox_.end());
    if (outbox_.empty()) send_close();
    if (shared_->stopping) {
      watch_timer_.expires_after(kWebSocketShutdownGrace);
    } else {
      watch_timer_.expires_after(kWebSocketCloseGrace);
    }
    watch_timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
      if (ec) return;
      beast::error_code ignored;
      beast::get_lowest_layer(self->ws_).socket().close(ignored);
    });
  }

  void send_close() {
    if (!ws_.is_open()) return;
    ws_.async_close(close_reason_, [self = shared_from_this()](beast::error_code) { self->watch_timer_.cancel(); });
  }

  /// Asks the peer about once a second whether the socket should end, so a socket that sends nothing
  /// learns that its session was deleted.
  void watch() {
    watch_timer_.expires_after(kWebSocketWatchInterval);
    watch_timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
      if (ec || self->closing_ || !self->ws_.is_open()) return;
      if (const std::string reason = self->peer_->close_reason(); !reason.empty()) {
        return self->end(beast::websocket::close_code::normal, reason);
      }
      self->watch();
    });
  }

  /// Starts pushing frames when the peer wants them and no timer runs yet.
  void schedule_push() {
    const double rate = peer_->push_rate();
    if (rate <= 0.0 || pushing_ || closing_) return;
    pushing_ = true;
    push_timer_.expires_after(std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1.0 / rate)));
    push_timer_.async_wait([self = shared_from_this()](beast::error_code ec) {
      if (ec || !self->ws_.is_open()) {
        self->pushing_ = false;
        return;
      }
      // The peer may have unsubscribed since the timer was set.
      if (self->peer_->push_rate() <= 0.0) {
        self->pushing_ = false;
        return;
      }
      self->push(self->peer_->push_frames(self->dropped_));
    });
  }

  /// Makes the deferred frames (on this worker), then sends them all at once, in order and next to each
  /// other (no answer comes between a state frame and its image); then the timer is set again, so the
  /// next push never overtakes these.
  void push(std::vector<Response> frames) {
    const std::uint64_t group = ++push_groups_;
    for (Response& frame : frames) {
      if (frame.deferred) frame = complete(std::move(frame), "a pushed WebSocket frame");
      // A frame that failed is left out; the subscription's next push tries again.
      if (frame.status < 400 && ws_.is_open()) send({std::move(frame.body), frame.content_type == kBinaryContentType, true, group});
    }
    pushing_ = false;
    if (ws_.is_open()) schedule_push();
  }

  beast::websocket::stream<beast::tcp_stream> ws_;
  std::shared_ptr<WebSocketPeer> peer_;
  std::shared_ptr<Shared> shared_;
  std::unique_ptr<Slot> slot_;
  beast::flat_buffer buffer_;
  net::steady_timer watch_timer_{ws_.get_executor()};  ///< asks the peer whether to end; then the close's grace
  bool closing_ = false;
  beast::websocket::close_reason close_reason_;
  std::deque<Outgoing> outbox_;  ///< waiting to be written, the first one being written
  net::steady_timer push_timer_{ws_.get_executor()};
  bool pushing_ = false;       ///< the push timer runs, or pushed frames are being made
  std::uint64_t dropped_ = 0;  ///< pushes (a state frame and its image) dropped for a slow reader
  std::uint64_t push_groups_ = 0;
};

std::string utc_timestamp() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm parts{};
  gmtime_r(&now, &parts);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &parts);
  return text;
}

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
    stream_.expires_after(shared_->options.read_timeout);
    bhttp::async_read_header(stream_, buffer_, *parser_,
                             beast::bind_front_handler(&Connection::on_header, shared_from_this()));
  }

  /// Clients that announce a body with "Expect: 100-continue" (curl does above 1 KiB) wait for an
  /// interim 100 before sending it; oversized bodies were already refused when the header was parsed.
  void on_header(beast::error_code ec, std::size_t bytes) {
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
    std::make_shared<WebSocketSession>(std::move(*socket), std::get<std::shared_ptr<WebSocketPeer>>(outcome), shared_, std::move(slot_))
        ->start(std::move(message));
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
    // A 204 has no body, so no type either.
    if (response.status != 204) message->set(bhttp::field::content_type, response.content_type);
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
  bool on_workers_;    ///< on a strand of the worker pool (see move_to_workers)
};

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
    auto slot = Slot::take(shared_, ignored ? std::string("unknown") : remote.address().to_string());
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

}  // namespace

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
    std::vector<std::shared_ptr<WebSocketSession>> sockets;
    {
      std::lock_guard lock(shared_->mutex);
      for (const auto& [key, weak] : shared_->websockets) {
        if (auto socket = weak.lock()) sockets.push_back(std::move(socket));
      }
    }
    for (const auto& socket : sockets) socket->close();
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
