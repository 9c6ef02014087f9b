// Session round trips on loopback against a running `hrisim serve` (bench/api_bench.sh starts one):
// REST `POST /step {"n":1,"action":[v,ω]}` on one keep-alive connection, and WebSocket lockstep `{"type":"step",…}`
// messages (also followed by the head camera's 256×256 RGB-D frame), both on a session of the bundled elevator scenario (six people, an HSR with laser, people
// detector and physics). Prints steps per second and the median and 99th-percentile round trip.
//   usage: api_bench PORT [seconds per case=5]
#include <algorithm>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

namespace {

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
using tcp = net::ip::tcp;
using Clock = std::chrono::steady_clock;
using nlohmann::json;

struct Figures {
  double steps_per_second;
  double median_us, p99_us;
};

Figures summarise(std::vector<double>& round_trips_us, double seconds) {
  std::sort(round_trips_us.begin(), round_trips_us.end());
  return {round_trips_us.size() / seconds, round_trips_us[round_trips_us.size() / 2], round_trips_us[round_trips_us.size() * 99 / 100]};
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

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: api_bench PORT [seconds=5]\n");
    return 2;
  }
  const auto port = static_cast<unsigned short>(std::atoi(argv[1]));
  const double seconds = argc > 2 ? std::atof(argv[2]) : 5.0;
  net::io_context io;
  const tcp::endpoint endpoint(net::ip::make_address("127.0.0.1"), port);

  beast::tcp_stream rest(io);
  rest.connect(endpoint);
  const std::string id = json::parse(request(rest, http::verb::post, "/api/v1/sessions", R"({"scenario": "elevator"})"))["id"];
  std::vector<double> trips;
  auto start = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - start).count() < seconds) {
    const auto before = Clock::now();
    const json reply = json::parse(request(rest, http::verb::post, "/api/v1/sessions/" + id + "/step", R"({"n": 1, "action": [0.1, 0.05]})"));
    trips.push_back(std::chrono::duration<double, std::micro>(Clock::now() - before).count());
    if (reply["status"] == "finished") request(rest, http::verb::post, "/api/v1/sessions/" + id + "/reset", "{}");
  }
  const Figures over_rest = summarise(trips, std::chrono::duration<double>(Clock::now() - start).count());

  beast::websocket::stream<tcp::socket> socket(io);
  socket.next_layer().connect(endpoint);
  socket.handshake("127.0.0.1", "/api/v1/sessions/" + id + "/ws");
  socket.text(true);
  trips.clear();
  // As learning code steps: one action per step; the reply carries the 48-value observation.
  const std::string step = R"({"type": "step", "n": 1, "action": [0.1, 0.05]})";
  std::size_t reply_bytes = 0;
  beast::flat_buffer buffer;
  start = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - start).count() < seconds) {
    const auto before = Clock::now();
    socket.write(net::buffer(step));
    socket.read(buffer);
    trips.push_back(std::chrono::duration<double, std::micro>(Clock::now() - before).count());
    reply_bytes = buffer.size();
    const bool finished = beast::buffers_to_string(buffer.data()).find("\"finished\"") != std::string::npos;
    buffer.consume(buffer.size());
    if (finished) request(rest, http::verb::post, "/api/v1/sessions/" + id + "/reset", "{}");
  }
  const Figures over_socket = summarise(trips, std::chrono::duration<double>(Clock::now() - start).count());

  // As the gesture task steps: one step, then the HSR head camera's 256×256 RGB-D frame (RGBA8 and
  // float32 depth: 512 KiB plus a 96-byte header) as a binary message.
  const std::string camera = R"({"type": "camera", "camera": "robot.head_rgbd", "width": 256, "height": 256})";
  std::size_t frame_bytes = 0;
  trips.clear();
  start = Clock::now();
  while (std::chrono::duration<double>(Clock::now() - start).count() < seconds) {
    const auto before = Clock::now();
    socket.write(net::buffer(step));
    socket.read(buffer);
    const bool finished = beast::buffers_to_string(buffer.data()).find("\"finished\"") != std::string::npos;
    buffer.consume(buffer.size());
    socket.write(net::buffer(camera));
    socket.read(buffer);
    trips.push_back(std::chrono::duration<double, std::micro>(Clock::now() - before).count());
    frame_bytes = buffer.size();
    buffer.consume(buffer.size());
    if (finished) request(rest, http::verb::post, "/api/v1/sessions/" + id + "/reset", "{}");
  }
  const Figures with_camera = summarise(trips, std::chrono::duration<double>(Clock::now() - start).count());

  // Two sessions stepped at once, each over its own WebSocket, 1000 steps per message: the worker
  // pool runs them in parallel.
  auto stepped_in = [&](int sessions) {
    std::vector<std::thread> clients;
    std::vector<double> steps_done(sessions, 0.0);
    const auto begin = Clock::now();
    for (int s = 0; s < sessions; ++s) {
      clients.emplace_back([&, s] {
        net::io_context own;
        beast::tcp_stream control(own);
        control.connect(endpoint);
        const std::string session = json::parse(request(control, http::verb::post, "/api/v1/sessions", R"({"scenario": "elevator"})"))["id"];
        beast::websocket::stream<tcp::socket> ws(own);
        ws.next_layer().connect(endpoint);
        ws.handshake("127.0.0.1", "/api/v1/sessions/" + session + "/ws");
        beast::flat_buffer reply;
        while (std::chrono::duration<double>(Clock::now() - begin).count() < seconds) {
          ws.write(net::buffer(std::string(R"({"type": "step", "n": 1000})")));
          ws.read(reply);
          const bool finished = beast::buffers_to_string(reply.data()).find("\"finished\"") != std::string::npos;
          reply.consume(reply.size());
          steps_done[s] += 1000;
          if (finished) request(control, http::verb::post, "/api/v1/sessions/" + session + "/reset", "{}");
        }
        request(control, http::verb::delete_, "/api/v1/sessions/" + session, "");
      });
    }
    for (std::thread& client : clients) client.join();
    double total = 0.0;
    for (const double done : steps_done) total += done;
    return total / std::chrono::duration<double>(Clock::now() - begin).count();
  };
  const double one = stepped_in(1), two = stepped_in(2);
  std::printf("api_bench: elevator session, one step and one action per round trip (reply %zu bytes), %.0f s per case\n", reply_bytes, seconds);
  std::printf("REST POST /step (keep-alive)   %8.0f steps/s   median %6.1f us   p99 %7.1f us\n", over_rest.steps_per_second,
              over_rest.median_us, over_rest.p99_us);
  std::printf("WebSocket lockstep step        %8.0f steps/s   median %6.1f us   p99 %7.1f us\n", over_socket.steps_per_second,
              over_socket.median_us, over_socket.p99_us);
  std::printf("WebSocket step + RGB-D frame    %8.0f steps/s   median %6.1f us   p99 %7.1f us   (frame %zu bytes)\n",
              with_camera.steps_per_second, with_camera.median_us, with_camera.p99_us, frame_bytes);
  std::printf("1 session,  1000 steps per message  %8.0f steps/s\n", one);
  std::printf("2 sessions, 1000 steps per message  %8.0f steps/s   (%.2fx one)\n", two, two / one);
  return 0;
}
