// Session round trips on loopback against a running `hrisim serve` (bench/api_bench.sh starts one),
// beside anchors this program measures itself in the same run: raw TCP ping-pong and a bare Beast
// WebSocket echo (one I/O thread answering on itself, whole-message frames), each with the reply size
// of the case it anchors.
//
// Cases: REST `POST /step {"n":1,"action":[v,ω]}` on one keep-alive connection; WebSocket lockstep
// `{"type":"step",…}` on the bundled elevator (six people, an HSR with laser, people detector and
// physics) and on perpendicular_crossing (six people, no robot); a step followed by the head camera's
// 256×256 RGB-D frame on the elevator and the apartment; and sessions stepped 1000 ticks per message.
// The step's own cost is measured in this process on the same scenario, seed and action (an episode
// stepped as the server steps it, recording included), so that each lockstep case also gives the
// server's overhead per round trip beyond the step, and its ratio to the echo's round trip. Run from
// the project's root (it reads scenarios/).
// Prints messages per second and the median and 99th-percentile round trip.
//   usage: api_bench PORT [seconds per case=5] [only the cases whose label contains this, to profile one]
#include <algorithm>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/read.hpp>
#include <boost/asio/write.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "episode/episode.hpp"
#include "scenario/load.hpp"

namespace {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

struct Figures {
  double per_second = 0.0;
  double median_us = 0.0, p99_us = 0.0;
};

/// Round trips timed one after another.
struct Trips {
  std::vector<double> us;
  double seconds = 0.0;

  /// Runs `round_trip` again and again for `duration` seconds, adding to these trips.
  void add(double duration, const std::function<void()>& round_trip) {
    const auto start = Clock::now();
    while (std::chrono::duration<double>(Clock::now() - start).count() < duration) {
      const auto before = Clock::now();
      round_trip();
      us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - before).count());
    }
    seconds += std::chrono::duration<double>(Clock::now() - start).count();
  }

  Figures figures() {
    std::sort(us.begin(), us.end());
    return {us.size() / seconds, us[us.size() / 2], us[us.size() * 99 / 100]};
  }
};

Figures timed(double seconds, const std::function<void()>& round_trip) {
  Trips trips;
  trips.add(seconds, round_trip);
  return trips.figures();
}

void print(const char* label, const Figures& figures, const std::string& note = "") {
  std::printf("%-46s %8.0f /s   median %7.1f us   p99 %7.1f us%s\n", label, figures.per_second, figures.median_us, figures.p99_us, note.c_str());
}

/// Anchor: a message of `ask` bytes answered by `answer` bytes over a plain TCP socket (Nagle off),
/// served by a blocking thread of this process.
class RawTcp {
 public:
  RawTcp(std::size_t ask, std::size_t answer)
      : acceptor_(io_, tcp::endpoint(net::ip::make_address("127.0.0.1"), 0)), client_(io_), out_(ask, 'x'), in_(answer, '\0') {
    server_ = std::thread([this, ask, answer] {
      tcp::socket peer = acceptor_.accept();
      peer.set_option(tcp::no_delay(true));
      std::string in(ask, '\0'), out(answer, 'x');
      beast::error_code ec;
      while (net::read(peer, net::buffer(in), ec), !ec) net::write(peer, net::buffer(out), ec);
    });
    client_.connect(acceptor_.local_endpoint());
    client_.set_option(tcp::no_delay(true));
  }
  ~RawTcp() {
    client_.close();
    server_.join();
  }
  void round_trip() {
    net::write(client_, net::buffer(out_));
    net::read(client_, net::buffer(in_));
  }

 private:
  net::io_context io_;
  tcp::acceptor acceptor_;
  tcp::socket client_;
  std::string out_, in_;
  std::thread server_;
};

/// Anchor: a bare Beast WebSocket server on one I/O thread of this process that answers each message
/// with `answer` bytes from that same thread, each answer one frame.
class BeastEcho {
 public:
  BeastEcho(std::string ask, std::size_t answer, bool binary)
      : acceptor_(io_, tcp::endpoint(net::ip::make_address("127.0.0.1"), 0)), reply_(answer, 'x'), peer_(io_), client_(own_), ask_(std::move(ask)) {
    acceptor_.async_accept([this, binary](beast::error_code ec, tcp::socket socket) {
      if (ec) return;
      socket.set_option(tcp::no_delay(true));
      beast::get_lowest_layer(peer_).socket() = std::move(socket);
      peer_.auto_fragment(false);
      peer_.binary(binary);
      peer_.async_accept([this](beast::error_code accept_ec) {
        if (!accept_ec) serve();
      });
    });
    server_ = std::thread([this] { io_.run(); });
    client_.next_layer().connect(acceptor_.local_endpoint());
    client_.next_layer().set_option(tcp::no_delay(true));
    client_.handshake("127.0.0.1", "/");
    client_.text(true);
  }
  ~BeastEcho() {
    client_.close(websocket::close_code::normal);
    server_.join();
  }
  void round_trip() {
    client_.write(net::buffer(ask_));
    client_.read(buffer_);
    buffer_.consume(buffer_.size());
  }

 private:
  void serve() {
    peer_.async_read(incoming_, [this](beast::error_code ec, std::size_t) {
      if (ec) return;
      incoming_.consume(incoming_.size());
      peer_.async_write(net::buffer(reply_), [this](beast::error_code write_ec, std::size_t) {
        if (!write_ec) serve();
      });
    });
  }

  net::io_context io_, own_;
  tcp::acceptor acceptor_;
  const std::string reply_;
  websocket::stream<beast::tcp_stream> peer_;
  beast::flat_buffer incoming_, buffer_;
  websocket::stream<tcp::socket> client_;
  std::string ask_;
  std::thread server_;
};

/// One HTTP request on an open keep-alive connection; the answer's body.
std::string request(beast::tcp_stream& stream, http::verb verb, const std::string& target, const std::string& body) {
  http::request<http::string_body> message(verb, target, 11);
  message.set(http::field::host, "127.0.0.1");
  message.set(http::field::content_type, "application/json");
  message.keep_alive(true);
  message.body() = body;
  message.prepare_payload();
  http::write(stream, message);
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  http::read(stream, buffer, response);
  if (response.result_int() >= 300) throw std::runtime_error(target + ": " + response.body());
  return response.body();
}

/// A live session of a bundled scenario with its REST connection and WebSocket; deleted at the end.
class Session {
 public:
  Session(net::io_context& io, const tcp::endpoint& server, const std::string& scenario) : rest_(io), socket_(io) {
    rest_.connect(server);
    id_ = json::parse(request(rest_, http::verb::post, "/api/v1/sessions", json{{"scenario", scenario}}.dump()))["id"];
    socket_.next_layer().connect(server);
    socket_.handshake("127.0.0.1", "/api/v1/sessions/" + id_ + "/ws");
    socket_.text(true);
  }
  ~Session() { request(rest_, http::verb::delete_, "/api/v1/sessions/" + id_, ""); }

  /// One message over the WebSocket and its answer's size; a finished session is reset.
  std::size_t send(const std::string& message) {
    socket_.write(net::buffer(message));
    socket_.read(buffer_);
    const std::size_t size = buffer_.size();
    const bool finished = !socket_.got_binary() && beast::buffers_to_string(buffer_.data()).find("\"finished\"") != std::string::npos;
    buffer_.consume(buffer_.size());
    if (finished) reset();
    return size;
  }

  /// A step over REST; a finished session is reset.
  std::size_t step_over_rest(const std::string& body) {
    const std::string reply = request(rest_, http::verb::post, "/api/v1/sessions/" + id_ + "/step", body);
    if (reply.find("\"finished\"") != std::string::npos) reset();
    return reply.size();
  }

 private:
  void reset() { request(rest_, http::verb::post, "/api/v1/sessions/" + id_ + "/reset", "{}"); }

  beast::tcp_stream rest_;
  websocket::stream<tcp::socket> socket_;
  beast::flat_buffer buffer_;
  std::string id_;
};

/// Microseconds one step of a bundled scenario takes in this process, stepped as a session steps it
/// (one env step with the action, recording on), resetting at its end; the mean over `seconds`.
double step_cost_us(const std::string& scenario, const std::optional<std::vector<double>>& action, double seconds) {
  std::ifstream file("scenarios/" + scenario + ".json");
  const auto loaded = hrisim::scenario::load_scenario(json::parse(file), {{"scenarios"}, {}});
  if (!loaded.model) throw std::runtime_error("cannot load scenarios/" + scenario + ".json");
  auto episode = std::make_unique<hrisim::episode::Episode>(loaded.model, 1);
  std::int64_t steps = 0;
  const auto start = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - start).count() < seconds) {
    for (int i = 0; i < 100; ++i, ++steps) {
      if (episode->over()) episode = std::make_unique<hrisim::episode::Episode>(loaded.model, 1);
      episode->step(action, 1);
    }
  }
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count() / static_cast<double>(steps);
}

/// A lockstep case, measured in rounds that alternate with the echo and with the step's own cost in
/// this process, so that all three see the same load on a shared machine: the figures, the step, the
/// overhead beyond it and its ratio to the echo's round trip.
void lockstep(const char* label, Session& session, const std::string& scenario, const std::optional<std::vector<double>>& action, BeastEcho& echo,
              double seconds) {
  constexpr int kRounds = 5;
  json message = {{"type", "step"}, {"n", 1}};
  if (action) message["action"] = *action;
  const std::string step = message.dump();
  Trips steps, echoes;
  double step_us = 0.0;
  for (int round = 0; round < kRounds; ++round) {
    echoes.add(seconds / kRounds / 4, [&] { echo.round_trip(); });
    step_us += step_cost_us(scenario, action, seconds / kRounds / 4) / kRounds;
    steps.add(seconds / kRounds / 2, [&] { session.send(step); });
  }
  const Figures figures = steps.figures(), echoed = echoes.figures();
  char note[200];
  std::snprintf(note, sizeof note, "\n%-46s step %.1f us; beyond it %.1f us = %.2fx the echo's %.1f us", "", step_us, figures.median_us - step_us,
                (figures.median_us - step_us) / echoed.median_us, echoed.median_us);
  print(label, figures, note);
}

/// Sessions stepped at once, each over its own WebSocket and thread, 1000 ticks per message: ticks per second.
double stepped_in(const tcp::endpoint& server, int sessions, double seconds) {
  std::vector<std::thread> clients;
  std::vector<double> ticks(sessions, 0.0);
  const auto begin = Clock::now();
  for (int s = 0; s < sessions; ++s) {
    clients.emplace_back([&, s] {
      net::io_context own;
      Session session(own, server, "elevator");
      while (std::chrono::duration<double>(Clock::now() - begin).count() < seconds) {
        session.send(R"({"type": "step", "n": 1000})");
        ticks[s] += 1000;
      }
    });
  }
  for (std::thread& client : clients) client.join();
  double total = 0.0;
  for (const double done : ticks) total += done;
  return total / std::chrono::duration<double>(Clock::now() - begin).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: api_bench PORT [seconds=5] [case]\n");
    return 2;
  }
  const auto port = static_cast<unsigned short>(std::atoi(argv[1]));
  const double seconds = argc > 2 ? std::atof(argv[2]) : 5.0;
  const std::string only = argc > 3 ? argv[3] : "";
  const auto wanted = [&](const std::string& label) { return label.find(only) != std::string::npos; };
  net::io_context io;
  const tcp::endpoint server(net::ip::make_address("127.0.0.1"), port);
  // As learning code steps: one action per step; the reply carries the 48-value observation.
  const std::vector<double> kAction{0.1, 0.05};
  const std::string step = R"({"type": "step", "n": 1, "action": [0.1, 0.05]})";
  const std::string camera = R"({"type": "camera", "camera": "robot.head_rgbd", "width": 256, "height": 256})";
  constexpr std::size_t kRgbdFrame = 96 + 256 * 256 * 8;  // header, RGBA8 and float32 depth

  std::printf("api_bench: one message and its answer per round trip, %.0f s per case\n", seconds);
  Session elevator(io, server, "elevator");
  const std::size_t reply_bytes = elevator.send(step);
  BeastEcho echo(step, reply_bytes, false);
  if (wanted("anchor")) {
    RawTcp small(100, 1024), large(100, kRgbdFrame);
    BeastEcho frame_echo(camera, kRgbdFrame, true);
    print("anchor: raw TCP 100 B -> 1 KiB", timed(seconds, [&] { small.round_trip(); }));
    print("anchor: raw TCP 100 B -> 512 KiB", timed(seconds, [&] { large.round_trip(); }));
    print("anchor: Beast WebSocket echo, step-sized reply", timed(seconds, [&] { echo.round_trip(); }), " (" + std::to_string(reply_bytes) + " B)");
    print("anchor: Beast WebSocket echo, 512 KiB reply", timed(seconds, [&] { frame_echo.round_trip(); }));
  }
  if (wanted("REST")) {
    print("REST POST /step (keep-alive), elevator", timed(seconds, [&] { elevator.step_over_rest(R"({"n": 1, "action": [0.1, 0.05]})"); }));
  }
  if (wanted("lockstep, elevator")) lockstep("WebSocket lockstep, elevator", elevator, "elevator", kAction, echo, seconds);
  if (wanted("lockstep, perpendicular_crossing")) {
    Session crossing(io, server, "perpendicular_crossing");
    lockstep("WebSocket lockstep, perpendicular_crossing", crossing, "perpendicular_crossing", std::nullopt, echo, seconds);
  }
  for (const char* scenario : {"elevator", "apartment"}) {
    const std::string label = "WebSocket step + RGB-D frame, " + std::string(scenario);
    if (!wanted(label)) continue;
    Session session(io, server, scenario);
    std::size_t frame_bytes = 0;
    const Figures figures = timed(seconds, [&] {
      session.send(step);
      frame_bytes = session.send(camera);
    });
    print(label.c_str(), figures, " (frame " + std::to_string(frame_bytes) + " B)");
  }
  if (wanted("ticks per message")) {
    const double one = stepped_in(server, 1, seconds), two = stepped_in(server, 2, seconds);
    std::printf("%-46s %8.0f ticks/s\n", "1 session,  1000 ticks per message", one);
    std::printf("%-46s %8.0f ticks/s   (%.2fx one)\n", "2 sessions, 1000 ticks per message", two, two / one);
  }
  return 0;
}
