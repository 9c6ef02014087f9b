#pragma once
// Live sessions over REST: create one from a scenario and a seed, read its status and state, step it
// (on the worker pool), delete it. Sessions have unguessable ids (128 random bits), expire when idle,
// and are limited in number (503 with Retry-After beyond).
#include <memory>
#include <string>
#include <vector>

#include "http/router.hpp"
#include "http/session_limits.hpp"
#include "http/session_work.hpp"
#include "http/scenario_catalogue.hpp"
#include "http/ws_tickets.hpp"

namespace hrisim::http {

/// `tickets`: issued by POST …/ws-ticket, for browsers that cannot send a token on an upgrade; `store`:
/// the stored episodes a session may replay.
void add_session_routes(Router& router, std::shared_ptr<ScenarioCatalogue> catalogue, SessionLimits limits, std::shared_ptr<TicketBook> tickets,
                        storage::Store* store);

}  // namespace hrisim::http
