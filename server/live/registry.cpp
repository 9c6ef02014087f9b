#include "live/registry.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "core/random.hpp"

namespace hrisim::live {
namespace {

/// A session whose episode is over. One busy with a request counts as running: its lock is not waited
/// for (the registry's is held).
bool finished(LiveSession& live) {
  std::unique_lock lock(live.mutex, std::try_to_lock);
  return lock && live.episode->over();
}

core::Error not_found(const std::string& id) { return core::Error(core::ErrorCode::not_found, "no session '" + id + "'", {{"id", id}}); }

}  // namespace

std::shared_ptr<void> Registry::admit_simulation(const std::string& owner) {
  std::lock_guard lock(simulations_->mutex);
  int& held = simulations_->held[owner];
  if (held >= kMaxSimulationsPerOwner) {
    throw core::Error(core::ErrorCode::unavailable,
                      "a restore or seek of yours is under way: one at a time, so that other sessions' steps are not held up",
                      {{"max_simulations", kMaxSimulationsPerOwner}, {"retry_after", kSimulationRetryAfter}});
  }
  ++held;
  return std::shared_ptr<void>(nullptr, [simulations = simulations_, owner](void*) {
    std::lock_guard lock(simulations->mutex);
    if (--simulations->held[owner] == 0) simulations->held.erase(owner);
  });
}

std::shared_ptr<LiveSession> Registry::create(NewSession request) {
  std::lock_guard lock(mutex_);
  expire_idle();
  std::vector<std::shared_ptr<LiveSession>> done;
  int running = 0;
  for (const auto& [id, live] : sessions_) {
    if (finished(*live)) {
      done.push_back(live);
    } else {
      ++running;
    }
  }
  if (running >= limits_.max_sessions) {
    throw core::Error(core::ErrorCode::unavailable,
                      "the server runs its maximum of " + std::to_string(limits_.max_sessions) +
                          " sessions (finished ones do not count): end one or retry later",
                      {{"max_sessions", limits_.max_sessions}, {"running", running}, {"retry_after", kSessionRetryAfter}});
  }
  // Finished sessions beyond the maximum: the least recently used that nobody watches go.
  std::sort(done.begin(), done.end(), [](const auto& a, const auto& b) { return a->last_used.load() < b->last_used.load(); });
  auto kept = static_cast<std::ptrdiff_t>(done.size());
  for (const auto& live : done) {
    if (kept <= limits_.max_sessions) break;
    if (*live->clients > 0) continue;
    sessions_.erase(live->id);
    --kept;
  }

  auto live = std::make_shared<LiveSession>();
  live->id = core::unguessable_id('s');
  live->scenario = std::move(request.scenario);
  live->seed = request.seed;
  live->mode = request.mode;
  live->realtime_factor = request.realtime_factor;
  live->controller = std::move(request.controller);
  live->owner = std::move(request.owner);
  live->unwatched_grace = request.unwatched_grace;
  live->episode_id = std::move(request.episode_id);
  live->time_limit = request.time_limit;
  live->requests = std::move(request.requests);
  live->scenario_sha256 = std::move(request.scenario_sha256);
  live->recording_memory = limits_.recording_memory;
  live->crowd_threads = limits_.crowd_threads;
  live->start(std::move(request.model));
  live->last_used = Clock::now();
  sessions_.emplace(live->id, live);
  return live;
}

std::shared_ptr<LiveSession> Registry::find(const std::string& id, const core::Caller& caller) {
  std::lock_guard lock(mutex_);
  expire_idle();
  const auto found = sessions_.find(id);
  if (found == sessions_.end() || !core::visible_to(caller, found->second->owner)) throw not_found(id);
  found->second->last_used = Clock::now();
  return found->second;
}

std::shared_ptr<LiveSession> Registry::find_if_live(const std::string& id) {
  std::lock_guard lock(mutex_);
  const auto found = sessions_.find(id);
  if (found == sessions_.end()) return nullptr;
  found->second->last_used = Clock::now();
  return found->second;
}

bool Registry::contains(const std::string& id) {
  std::lock_guard lock(mutex_);
  return sessions_.contains(id);
}

void Registry::remove(const std::string& id, const core::Caller& caller) {
  std::lock_guard lock(mutex_);
  const auto found = sessions_.find(id);
  if (found == sessions_.end() || !core::visible_to(caller, found->second->owner)) throw not_found(id);
  sessions_.erase(found);
}

std::vector<std::shared_ptr<LiveSession>> Registry::all(const core::Caller& caller) {
  std::lock_guard lock(mutex_);
  expire_idle();
  std::vector<std::shared_ptr<LiveSession>> list;
  for (const auto& [id, live] : sessions_) {
    if (core::visible_to(caller, live->owner)) list.push_back(live);
  }
  return list;
}

void Registry::expire_idle() {
  const auto now = Clock::now();
  std::erase_if(sessions_, [&](const auto& entry) {
    const LiveSession& live = *entry.second;
    if (*live.clients > 0) return false;
    const auto unused = now - live.last_used.load();
    return unused > limits_.idle_timeout || (live.unwatched_grace && unused > *live.unwatched_grace);
  });
}

/// A session busy with a request is skipped this time; one that fell far behind skips ahead in wall
/// time (it never steps more than kRealtimeMaxCatchUp at once).
void Registry::step_realtime(std::stop_token stop) {
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kRealtimeTick));
  const int ticks_per_expiry = static_cast<int>(1.0 / kRealtimeTick);
  auto next = Clock::now();
  for (int round = 1; !stop.stop_requested(); ++round) {
    next += period;
    std::this_thread::sleep_until(next);
    std::vector<std::shared_ptr<LiveSession>> realtime;
    {
      std::lock_guard lock(mutex_);
      if (round % ticks_per_expiry == 0) expire_idle();  // a closed tab's session goes without waiting for a request
      for (const auto& [id, live] : sessions_) {
        if (live->mode == Mode::realtime) realtime.push_back(live);
      }
    }
    const auto now = Clock::now();
    for (const auto& live : realtime) {
      std::unique_lock lock(live->mutex, std::try_to_lock);
      if (!lock) continue;
      const sim::Session& session = live->session();
      const double dt = session.model().dt;
      const double elapsed = std::chrono::duration<double>(now - live->realtime_origin).count() * live->realtime_factor;
      const auto due = live->realtime_origin_tick + static_cast<std::int64_t>(elapsed / dt);
      // At most what two ticks of wall clock are worth at this factor, and kRealtimeMaxCatchUp at least.
      const auto most = static_cast<std::int64_t>(std::max(kRealtimeMaxCatchUp, 2.0 * kRealtimeTick * live->realtime_factor) / dt);
      std::int64_t steps = due - session.state().tick;
      if (steps > most) {
        // Too far behind: start the clock again from here rather than rushing.
        steps = most;
        live->realtime_origin = now;
        live->realtime_origin_tick = session.state().tick + most;
      }
      for (std::int64_t i = 0; i < steps && !live->episode->over(); ++i) live->episode->tick();
    }
  }
}

}  // namespace hrisim::live
