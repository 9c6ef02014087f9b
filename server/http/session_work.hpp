#pragma once
// How http answers on a live session (live::Registry): with the session's lock held, at once or on the
// worker pool, and restores and seeks holding their owner's place (live::Registry::admit_simulation).
#include <functional>
#include <memory>

#include "http/router.hpp"
#include "live/live_session.hpp"
#include "live/registry.hpp"

namespace hrisim::http {

// The live-session service's names as http, one of its front ends, uses them (a variable named `live`
// is everywhere here, and would hide the namespace).
using live::Clock;
using live::LiveSession;
using live::Mode;
using live::parse_mode;
using live::NewSession;
using live::Registry;
using live::SessionLimits;
using live::kMaxRealtimeFactor;
using live::kMaxSnapshots;
using live::kMaxUnwatchedGrace;
using live::kSessionRetryAfter;
using live::kSimulationRetryAfter;

/// Answers with the session's lock held: at once when it is free, else on the worker pool, so that an
/// I/O thread never waits behind a long step (health checks and other sessions stay answered).
Response locked(std::shared_ptr<LiveSession> live, std::function<Response(LiveSession&)> work);

/// Does a restore's or seek's `work` on the worker pool holding `place` (live::Registry::admit_simulation),
/// given back as soon as the work ends, before its answer is sent: the owner's next one may follow it
/// at once instead of finding the place still taken.
Response simulation_later(std::shared_ptr<void> place, std::function<Response()> work);

}  // namespace hrisim::http
