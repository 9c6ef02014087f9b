// A WebSocket peer (router.hpp) served on a strand of the worker pool (see server_shared.hpp).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <set>
#include <vector>

#include <boost/asio/dispatch.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include "http/server_shared.hpp"

namespace hrisim::http::serving {

/// Largest WebSocket message accepted; bigger ones close the connection (code 1009).
constexpr std::size_t kMaxWebSocketMessage = 1 << 20;

/// Pushes (a state frame with its image, if any) waiting behind the write in flight at most; the
/// oldest is dropped for a newer one.
constexpr std::size_t kMaxQueuedFrames = 4;

/// How often a WebSocket asks its peer whether it should end.
constexpr std::chrono::seconds kWebSocketWatchInterval{1};

/// After a close frame the server sent, the socket is cut this long later if the close has not completed
/// (shorter when the server shuts down: it waits for every socket).
constexpr std::chrono::seconds kWebSocketCloseGrace{5};
constexpr std::chrono::milliseconds kWebSocketShutdownGrace{500};

/// A WebSocket connection: the peer's greeting queued, then one message (text or binary) read,
/// answered, its answer queued, then the next read — so answers come in the order of the messages. The socket lives on a strand of the worker pool, so a
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
    if (std::string subprotocol = peer_->subprotocol(); !subprotocol.empty()) {
      ws_.set_option(beast::websocket::stream_base::decorator([subprotocol = std::move(subprotocol)](beast::websocket::response_type& answer) {
        answer.set(bhttp::field::sec_websocket_protocol, subprotocol);
      }));
    }
    ws_.async_accept(upgrade, [self = shared_from_this()](beast::error_code ec) {
      if (ec) return;
      self->greet();
      self->schedule_push();  // a peer that pushes from the start (the time) needs no message first
      self->read();
      self->watch();
    });
  }

  /// On shutdown: a normal close.
  void close() {
    net::dispatch(ws_.get_executor(), [self = shared_from_this()] { self->end(beast::websocket::close_code::going_away, ""); });
  }

 private:
  /// The peer's greeting, made on this worker and queued before any answer.
  void greet() {
    std::vector<Response> greeting;
    try {
      greeting = peer_->on_open();
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hrisim: internal error opening a WebSocket: %s\n", e.what());
      return end(beast::websocket::close_code::internal_error, "internal error");
    }
    for (Response& message : greeting) {
      message = complete(std::move(message), "a WebSocket's greeting");
      if (!message.is_nothing()) send({std::move(message.body), message.content_type == kBinaryContentType, false});
    }
  }

  void read() {
    if (closing_) return;
    if (const std::string reason = peer_->close_reason(); !reason.empty()) return end(beast::websocket::close_code::normal, reason);
    ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
      if (ec) return self->drop();  // closed, timed out or too big: Beast has told the peer
      WebSocketMessage message{beast::buffers_to_string(self->buffer_.data()), self->ws_.got_binary()};
      self->buffer_.consume(self->buffer_.size());
      self->answer(std::move(message));
    });
  }

  void answer(WebSocketMessage message) {
    Response response;
    try {
      response = peer_->on_message(message);
    } catch (const core::Error& e) {
      response = Response::error(e);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "hrisim: internal error on a WebSocket message: %s\n", e.what());
      response = Response::error(core::Error(core::ErrorCode::internal, "internal error"));
    }
    // Already on a worker: deferred work runs here, and the answer is sent from this strand.
    answer_on_workers(*shared_->workers, std::move(response), "a WebSocket", [self = shared_from_this()](Response answer) {
      net::dispatch(self->ws_.get_executor(), [self, answer = std::move(answer)]() mutable {
        if (!answer.is_nothing()) self->send({std::move(answer.body), answer.content_type == kBinaryContentType, false});
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
      if (ec) return self->drop();
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

  /// The peer is gone (its read or a write failed): the socket and its place are given up at once, not
  /// when a timer next looks, so a client that drops sockets in a loop never holds more than it has open.
  /// A close the server began is left to its grace timer.
  void drop() {
    if (closing_) return;
    closing_ = true;
    push_timer_.cancel();
    watch_timer_.cancel();
    beast::error_code ignored;
    beast::get_lowest_layer(ws_).socket().close(ignored);
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

  /// Starts pushing frames when the peer wants them and no timer runs yet: a period after the last push
  /// was due, so that the time a push takes does not slow the rate (at once when that time is past).
  void schedule_push() {
    const double rate = peer_->push_rate();
    if (rate <= 0.0 || pushing_ || closing_) return;
    pushing_ = true;
    const auto period = std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(1.0 / rate));
    push_due_ = std::max(push_due_ + period, std::chrono::steady_clock::now());
    push_timer_.expires_at(push_due_);
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
      if (frame.status < 400 && !frame.is_nothing() && ws_.is_open()) send({std::move(frame.body), frame.content_type == kBinaryContentType, true, group});
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
  std::chrono::steady_clock::time_point push_due_{};  ///< when the last push was due
  std::uint64_t dropped_ = 0;  ///< pushes (a state frame and its image) dropped for a slow reader
  std::uint64_t push_groups_ = 0;
};

void start_websocket(tcp::socket&& socket, std::shared_ptr<WebSocketPeer> peer, std::shared_ptr<Shared> shared,
                     std::unique_ptr<Slot> slot, bhttp::request<bhttp::string_body> upgrade) {
  std::make_shared<WebSocketSession>(std::move(socket), std::move(peer), std::move(shared), std::move(slot))->start(std::move(upgrade));
}

void close_websockets(Shared& shared) {
  std::vector<std::shared_ptr<WebSocketSession>> sockets;
  {
    std::lock_guard lock(shared.mutex);
    for (const auto& [key, weak] : shared.websockets) {
      if (auto socket = weak.lock()) sockets.push_back(std::move(socket));
    }
  }
  for (const auto& socket : sockets) socket->close();
}

}  // namespace hrisim::http::serving
