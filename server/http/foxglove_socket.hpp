#pragma once
// A live session as a Foxglove WebSocket server (docs/foxglove.md): Foxglove and Lichtblick open
// /api/v1/sessions/{id}/foxglove and see its scene, frames, lasers, cameras, detections, events and
// metrics as channels, drive its robot by publishing a velocity, and step, reset and seek it as services.
#include <memory>

#include "http/router.hpp"
#include "http/session_work.hpp"

namespace hrisim::http {

/// The Foxglove socket of `live` for `caller`, upgraded from `upgrade`: its subprotocol agreed (400
/// when it offers neither foxglove.sdk.v1 nor foxglove.websocket.v1) and its query read (rate,
/// image_rate, image_width, image_height; 400 naming a bad one). It holds no reference to the session.
std::shared_ptr<WebSocketPeer> open_foxglove_socket(std::shared_ptr<Registry> registry, const std::shared_ptr<LiveSession>& live,
                                                    const Request& upgrade);

}  // namespace hrisim::http
