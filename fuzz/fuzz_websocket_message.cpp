// Fuzz target: a session's WebSocket messages (step, commands, state, sensors, laser, camera,
// subscribe), answered as the server answers them, pushed frames included, on a session of the
// elevator with its robot.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_server.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  hrisim::fuzz::Server& server = hrisim::fuzz::server();
  const std::string text(reinterpret_cast<const char*>(data), size);
  hrisim::http::WebSocketPeer& peer = server.socket();
  hrisim::fuzz::check_reply(hrisim::fuzz::Server::settle(peer.on_message({text, false})));
  if (peer.push_rate() > 0.0) {
    for (hrisim::http::Response& frame : peer.push_frames(0)) hrisim::fuzz::Server::settle(std::move(frame));
  }
  (void)peer.close_reason();
  return 0;
}
