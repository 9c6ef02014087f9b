#pragma once
// A live session as a rosbridge v2 server (docs/rosbridge.md): roslibjs, roslibpy and Lichtblick's
// rosbridge player open /api/v1/sessions/{id}/rosbridge and see its clock, transforms, lasers,
// odometry, people, events and cameras as ROS 2 topics, drive its robot with a Twist on /cmd_vel, ask
// rosapi about its topics, and reset, step and seek it as services.
#include <memory>

#include "http/router.hpp"
#include "http/session_work.hpp"

namespace hrisim::http {

/// The rosbridge socket of `live` for the upgrade's caller, its query read (rate, image_rate: 400
/// naming a bad one). It holds no reference to the session.
std::shared_ptr<WebSocketPeer> open_rosbridge_socket(std::shared_ptr<Registry> registry, const std::shared_ptr<LiveSession>& live,
                                                     const Request& upgrade);

}  // namespace hrisim::http
