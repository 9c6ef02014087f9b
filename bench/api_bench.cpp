// Session round trips on loopback against a running `hrisim serve` (bench/api_bench.sh starts one),
// beside anchors this program measures itself in the same run: raw TCP ping-pong and a bare Beast
// WebSocket echo (one I/O thread answering on itself, whole-message frames), each with the reply size
// of the case it anchors.
//
// Cases: REST `POST /step {"n":1,"action":[v,ω]}` on one keep-alive connection; WebSocket lockstep
// `{"type":"step",…}` on the bundled elevator (six people, an HSR with laser, people detector and
// physics) and on perpendicular_crossing (six people, no robot); a step followed by the head camera's
// 256×256 RGB-D frame on the elevator and the apartment; and sessions stepped 1000 ticks per message.
// The step's own cost is measured by those 1000-tick messages, so that each lockstep case also gives
// the server's overhead per round trip beyond the step, and its ratio to the echo's round trip.
// Prints messages per second and the median and 99th-percentile round trip.
//   usage: api_bench PORT [seconds per case=5]
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
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

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

/// Runs `round_trip` again and again for `seconds`; its rate and latencies.
Figures timed(double seconds, const std::function<void()>& round_trip) {
  std::vector<double> trips;
  const auto start = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - start).count() < seconds) {
    const auto before = Clock::now();
    round_trip();
    trips.push_back(std::chrono::duration<double, std::micro>(Clock::now() - before).count());
  }
  const double elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  std::sort(trips.begin(), trips.end());
  return {trips.size() / elapsed, trips[trips.size() / 2], trips[trips.size() * 99 / 100]};
}

void print(const char* label, const Figures& figures, const std::string& note = "") {
  std::printf("%-46s %8.0f /s   median %7.1f us   p99 %7.1f us%s\n", label, figures.per_second, figures.median_us, figures.p99_us, note.c_str());
}

/// Anchor: a message of `ask` bytes answered by `answer` bytes over a plain TCP socket (Nagle off),
/// served by a blocking thread of this process.
Figures raw_tcp(std::size_t ask, std::size_t answer, double seconds) {
  net::io_context io;
  tcp::acceptor acceptor(io, tcp::endpoint(net::ip::make_address("127.0.0.1"), 0));
  std::thread server([&] {
    tcp::socket peer = acceptor.accept();
    peer.set_option(tcp::no_delay(true));
    std::string in(ask, '\0'), out(answer, 'x');
    beast::error_code ec;
    while (net::read(peer, net::buffer(in), ec), !ec) net::write(peer, net::buffer(out), ec);
  });
  tcp::socket client(io);
  client.connect(acceptor.local_endpoint());
  client.set_option(tcp::no_delay(true));
  std::string out(ask, 'x'), in(answer, '\0');
  const Figures figures = timed(seconds, [&] {
    net::write(client, net::buffer(out));
    net::read(client, net::buffer(in));
  });
  client.close();
  server.join();
  return figures;
}

/// Anchor: a bare Beast WebSocket server on one I/O thread of this process that answers each message
/// with `answer` bytes from that same thread, each answer one frame.
Figures beast_echo(const std::string& ask, std::size_t answer, bool binary, double seconds) {
  net::io_context io;
  tcp::acceptor acceptor(io, tcp::endpoint(net::ip::make_address("127.0.0.1"), 0));
  const std::string reply(answer, 'x');
  websocket::stream<beast::tcp_stream> peer(io);
  beast::flat_buffer incoming;
  std::function<void()> serve = [&] {
    peer.async_read(incoming, [&](beast::error_code ec, std::size_t) {
      if (ec) return;
      incoming.consume(incoming.size());
      peer.async_write(net::buffer(reply), [&](beast::error_code write_ec, std::size_t) {
        if (!write_ec) serve();
      });
    });
  };
  acceptor.async_accept([&](beast::error_code ec, tcp::socket socket) {
    if (ec) return;
    socket.set_option(tcp::no_delay(true));
    beast::get_lowest_layer(peer).socket() = std::move(socket);
    peer.auto_fragment(false);
    peer.binary(binary);
    peer.async_accept([&](beast::error_code accept_ec) {
      if (!accept_ec) serve();
    });
  });
  std::thread server([&] { io.run(); });
  net::io_context own;
  websocket::stream<tcp::socket> client(own);
  client.next_layer().connect(acceptor.local_endpoint());
  client.next_layer().set_option(tcp::no_delay(true));
  client.handshake("127.0.0.1", "/");
  client.text(true);
  beast::flat_buffer buffer;
  const Figures figures = timed(seconds, [&] {
    client.write(net::buffer(ask));
    client.read(buffer);
    buffer.consume(buffer.size());
  });
  client.close(websocket::close_code::normal);
  server.join();
  return figures;
}

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

/// Microseconds a tick of the session takes in the server, from messages of 1000 ticks each.
double tick_cost_us(Session& session, double seconds) {
  const Figures batched = timed(seconds, [&] { session.send(R"({"type": "step", "n": 1000})"); });
  return batched.median_us / 1000.0;
}

/// A lockstep case: its figures, the tick's own cost, the overhead beyond it and its ratio to the echo.
void lockstep(const char* label, Session& session, const std::string& step, const Figures& echo, double seconds) {
  const double tick_us = tick_cost_us(session, seconds / 2);
  const Figures figures = timed(seconds, [&] { session.send(step); });
  char note[160];
  std::snprintf(note, sizeof note, "\n%-46s tick %.1f us; beyond it %.1f us = %.2fx the echo", "", tick_us, figures.median_us - tick_us,
                (figures.median_us - tick_us) / echo.median_us);
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
    std::fprintf(stderr, "usage: api_bench PORT [seconds=5]\n");
    return 2;
  }
  const auto port = static_cast<unsigned short>(std::atoi(argv[1]));
  const double seconds = argc > 2 ? std::atof(argv[2]) : 5.0;
  net::io_context io;
  const tcp::endpoint server(net::ip::make_address("127.0.0.1"), port);
  // As learning code steps: one action per step; the reply carries the 48-value observation.
  const std::string step = R"({"type": "step", "n": 1, "action": [0.1, 0.05]})";
  const std::string camera = R"({"type": "camera", "camera": "robot.head_rgbd", "width": 256, "height": 256})";
  constexpr std::size_t kRgbdFrame = 96 + 256 * 256 * 8;  // header, RGBA8 and float32 depth

  std::printf("api_bench: one message and its answer per round trip, %.0f s per case\n", seconds);
  Session elevator(io, server, "elevator");
  const std::size_t reply_bytes = elevator.send(step);
  const Figures echo = beast_echo(step, reply_bytes, false, seconds);
  print("anchor: raw TCP 100 B -> 1 KiB", raw_tcp(100, 1024, seconds));
  print("anchor: raw TCP 100 B -> 512 KiB", raw_tcp(100, kRgbdFrame, seconds));
  print("anchor: Beast WebSocket echo, step-sized reply", echo, " (" + std::to_string(reply_bytes) + " B)");
  const Figures frame_echo = beast_echo(camera, kRgbdFrame, true, seconds);
  print("anchor: Beast WebSocket echo, 512 KiB reply", frame_echo);

  print("REST POST /step (keep-alive), elevator", timed(seconds, [&] { elevator.step_over_rest(R"({"n": 1, "action": [0.1, 0.05]})"); }));
  lockstep("WebSocket lockstep, elevator", elevator, step, echo, seconds);
  {
    Session crossing(io, server, "perpendicular_crossing");
    lockstep("WebSocket lockstep, perpendicular_crossing", crossing, R"({"type": "step", "n": 1})", echo, seconds);
  }
  for (const char* scenario : {"elevator", "apartment"}) {
    Session session(io, server, scenario);
    std::size_t frame_bytes = 0;
    const Figures figures = timed(seconds, [&] {
      session.send(step);
      frame_bytes = session.send(camera);
    });
    print(("WebSocket step + RGB-D frame, " + std::string(scenario)).c_str(), figures, " (frame " + std::to_string(frame_bytes) + " B)");
  }
  const double one = stepped_in(server, 1, seconds), two = stepped_in(server, 2, seconds);
  std::printf("%-46s %8.0f ticks/s\n", "1 session,  1000 ticks per message", one);
  std::printf("%-46s %8.0f ticks/s   (%.2fx one)\n", "2 sessions, 1000 ticks per message", two, two / one);
  return 0;
}
