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

WebSocketClient::WebSocketClient(std::uint16_t port, const std::string& target, const std::string& authorization, int receive_buffer,
                                 const std::string& subprotocols)
    : socket_(std::make_unique<Socket>()) {
  auto& ws = socket_->ws;
  net::ip::tcp::endpoint endpoint(net::ip::make_address("127.0.0.1"), port);
  ws.next_layer().open(endpoint.protocol());
  if (receive_buffer > 0) ws.next_layer().set_option(net::socket_base::receive_buffer_size(receive_buffer));
  ws.next_layer().connect(endpoint);
  ws.set_option(beast::websocket::stream_base::decorator([authorization, subprotocols](beast::websocket::request_type& request) {
    if (!authorization.empty()) request.set(beast::http::field::authorization, authorization);
    if (!subprotocols.empty()) request.set(beast::http::field::sec_websocket_protocol, subprotocols);
  }));
  beast::websocket::response_type response;
  beast::error_code ec;
  ws.handshake(response, "127.0.0.1", target, ec);
  if (ec) status = static_cast<int>(response.result_int());
  subprotocol = std::string(response[beast::http::field::sec_websocket_protocol]);
}

WebSocketClient::~WebSocketClient() = default;

void WebSocketClient::send_text(const std::string& text) {
  socket_->ws.text(true);
  socket_->ws.write(net::buffer(text));
}

void WebSocketClient::send_binary(const std::string& bytes) {
  socket_->ws.binary(true);
  socket_->ws.write(net::buffer(bytes));
}

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
