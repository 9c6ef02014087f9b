#pragma once
// A blocking WebSocket client on loopback (Boost.Beast), for the API tests of session sockets. Beast
// stays in websocket_client.cpp: its templates are instantiated once, not in every test file.
#include <cstdint>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "test_server.hpp"

namespace hrisim::testing {

/// The HTTP answer to a WebSocket upgrade request, written by hand (a refused upgrade's status and body).
HttpReply upgrade(std::uint16_t port, const std::string& target, const std::string& extra_headers = "");

class WebSocketClient {
 public:
  /// Connects and upgrades; `status` is non-zero when the upgrade was refused (see upgrade() for its reply). A
  /// `receive_buffer` > 0 shrinks the socket's receive buffer (a client that reads slowly fills up sooner).
  /// `subprotocols`: the Sec-WebSocket-Protocol offered ("a, b"), none when empty.
  WebSocketClient(std::uint16_t port, const std::string& target, const std::string& authorization = "", int receive_buffer = 0,
                  const std::string& subprotocols = "");
  ~WebSocketClient();
  WebSocketClient(const WebSocketClient&) = delete;
  WebSocketClient& operator=(const WebSocketClient&) = delete;

  nlohmann::json exchange(const nlohmann::json& message) {
    send(message);
    return nlohmann::json::parse(next());
  }
  void send(const nlohmann::json& message) { send_text(message.dump()); }
  /// Sends text as it is (not necessarily JSON) and reads the answer.
  std::string exchange_text(const std::string& text) {
    send_text(text);
    return next();
  }
  void send_text(const std::string& text);
  void send_binary(const std::string& bytes);
  /// The subprotocol the server agreed to (its answer's Sec-WebSocket-Protocol), empty for none.
  std::string subprotocol;
  /// The next message from the server, as bytes; `binary` says whether it came as a binary message.
  /// Throws boost::system::system_error (a std::exception) when the socket closes (see close_code()).
  std::string next(bool* binary = nullptr);
  /// The code and reason of the close frame the server sent, once a read has failed with "closed".
  int close_code() const;
  std::string close_reason() const;

  int status = 0;

 private:
  struct Socket;
  std::unique_ptr<Socket> socket_;
};

}  // namespace hrisim::testing
