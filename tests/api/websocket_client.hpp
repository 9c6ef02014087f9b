#pragma once
// A blocking WebSocket client on loopback (Boost.Beast), for the API tests of session sockets.
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

#include "test_server.hpp"

namespace hrisim::testing {

/// The HTTP answer to a WebSocket upgrade request, written by hand (a refused upgrade's status and body).
inline HttpReply upgrade(std::uint16_t port, const std::string& target, const std::string& extra_headers = "") {
  RawConnection connection(port);
  connection.send("GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: Upgrade\r\nUpgrade: websocket\r\n"
                  "Sec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n" + extra_headers + "\r\n");
  return connection.read_reply();
}

class WebSocketClient {
 public:
  /// Connects and upgrades; `status` is non-zero when the upgrade was refused (see upgrade() for its reply). A
  /// `receive_buffer` > 0 shrinks the socket's receive buffer (a client that reads slowly fills up sooner).
  WebSocketClient(std::uint16_t port, const std::string& target, const std::string& authorization = "", int receive_buffer = 0) {
    namespace net = boost::asio;
    namespace beast = boost::beast;
    net::ip::tcp::endpoint endpoint(net::ip::make_address("127.0.0.1"), port);
    ws_.next_layer().open(endpoint.protocol());
    if (receive_buffer > 0) ws_.next_layer().set_option(net::socket_base::receive_buffer_size(receive_buffer));
    ws_.next_layer().connect(endpoint);
    ws_.set_option(beast::websocket::stream_base::decorator([authorization](beast::websocket::request_type& request) {
      if (!authorization.empty()) request.set(beast::http::field::authorization, authorization);
    }));
    beast::websocket::response_type response;
    beast::error_code ec;
    ws_.handshake(response, "127.0.0.1", target, ec);
    if (ec) status = static_cast<int>(response.result_int());
  }

  nlohmann::json exchange(const nlohmann::json& message) {
    send(message);
    return nlohmann::json::parse(next());
  }
  void send(const nlohmann::json& message) { ws_.write(boost::asio::buffer(message.dump())); }
  /// Sends text as it is (not necessarily JSON) and reads the answer.
  std::string exchange_text(const std::string& text) {
    ws_.write(boost::asio::buffer(text));
    return next();
  }
  /// The next message from the server, as bytes; `binary` says whether it came as a binary message.
  /// Throws boost::system::system_error when the socket closes (see close_code()).
  std::string next(bool* binary = nullptr) {
    boost::beast::flat_buffer buffer;
    ws_.read(buffer);
    if (binary) *binary = ws_.got_binary();
    return boost::beast::buffers_to_string(buffer.data());
  }
  /// The code and reason of the close frame the server sent, once a read has failed with "closed".
  int close_code() const { return ws_.reason().code; }
  std::string close_reason() const { return std::string(ws_.reason().reason.data(), ws_.reason().reason.size()); }

  int status = 0;

 private:
  boost::asio::io_context io_;
  boost::beast::websocket::stream<boost::asio::ip::tcp::socket> ws_{io_};
};

}  // namespace hrisim::testing
