#include "websocket_client.hpp"

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

namespace hrisim::testing {

namespace net = boost::asio;
namespace beast = boost::beast;

struct WebSocketClient::Socket {
  net::io_context io;
  beast::websocket::stream<net::ip::tcp::socket> ws{io};
};

HttpReply upgrade(std::uint16_t port, const std::string& target, const std::string& extra_headers) {
  RawConnection connection(port);
  connection.send("GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: Upgrade\r\nUpgrade: websocket\r\n"
                  "Sec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n" + extra_headers + "\r\n");
  return connection.read_reply();
}

WebSocketClient::WebSocketClient(std::uint16_t port, const std::string& target, const std::string& authorization, int receive_buffer)
    : socket_(std::make_unique<Socket>()) {
  auto& ws = socket_->ws;
  net::ip::tcp::endpoint endpoint(net::ip::make_address("127.0.0.1"), port);
  ws.next_layer().open(endpoint.protocol());
  if (receive_buffer > 0) ws.next_layer().set_option(net::socket_base::receive_buffer_size(receive_buffer));
  ws.next_layer().connect(endpoint);
  ws.set_option(beast::websocket::stream_base::decorator([authorization](beast::websocket::request_type& request) {
    if (!authorization.empty()) request.set(beast::http::field::authorization, authorization);
  }));
  beast::websocket::response_type response;
  beast::error_code ec;
  ws.handshake(response, "127.0.0.1", target, ec);
  if (ec) status = static_cast<int>(response.result_int());
}

WebSocketClient::~WebSocketClient() = default;

void WebSocketClient::send_text(const std::string& text) { socket_->ws.write(net::buffer(text)); }

std::string WebSocketClient::next(bool* binary) {
  beast::flat_buffer buffer;
  socket_->ws.read(buffer);
  if (binary) *binary = socket_->ws.got_binary();
  return beast::buffers_to_string(buffer.data());
}

int WebSocketClient::close_code() const { return socket_->ws.reason().code; }

std::string WebSocketClient::close_reason() const {
  return std::string(socket_->ws.reason().reason.data(), socket_->ws.reason().reason.size());
}

}  // namespace hrisim::testing
