#pragma once
// A live session's WebSocket: lockstep messages answered one each, in order, and state frames pushed
// at the rate a client subscribed to. The protocol is a table from message type to handler.
#include <memory>

#include "http/session_work.hpp"
#include "http/router.hpp"

namespace hrisim::http {

/// The socket of `live` for `caller`; it holds no reference to the session (a deleted one is freed,
/// and the socket then closes).
std::shared_ptr<WebSocketPeer> open_session_socket(std::shared_ptr<Registry> registry, const std::shared_ptr<LiveSession>& live, Caller caller);

}  // namespace hrisim::http
