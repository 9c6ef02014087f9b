#pragma once
// Live sessions, private to http: what the server keeps for each one (its episode, mode, snapshots,
// viewers) and the registry that creates, finds, expires and — for realtime sessions — steps them by
// the wall clock.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "core/memory_budget.hpp"
#include "core/random.hpp"
#include "episode/episode.hpp"
#include "http/router.hpp"
#include "http/session_limits.hpp"

namespace hrisim::http {

using Clock = std::chrono::steady_clock;

/// A live session records at most this many bodies (people and robot, summed over its steps) for its
/// metrics on demand: packed, 120–250 MB (memory_bench: 15–32 B a body), 5 hours of the elevator's
/// six people and HSR at 60 Hz, two minutes of a thousand people. Its metrics then cover the steps
/// up to `recorded_until_tick`.
inline constexpr std::size_t kMaxLiveRecordedBodies = 8'000'000;

struct Live {
  std::string id, scenario;
  std::string owner;  ///< who created it (the token's name); empty without owners
  std::int64_t seed = 0;
  std::string mode = "lockstep";  ///< lockstep: clients step it; realtime: the server does, by the wall clock
  double realtime_factor = 1.0;   ///< realtime: simulated seconds per wall-clock second
  std::optional<nlohmann::json> controller;  ///< replaced the robot under test's, when given
  std::mutex mutex;  ///< one request at a time works on the session
  std::unique_ptr<episode::Episode> episode;
  core::MemoryBudget* recording_memory = nullptr;  ///< shared by every recording of the server
  unsigned crowd_threads = 1;  ///< threads computing the crowd's velocities (`--crowd-threads`)
  std::size_t events_reported = 0;  ///< events before this index were in a step reply already
  std::uint64_t generation = 0;     ///< counts resets and restores, so that viewers notice a fresh start
  std::map<std::string, episode::Episode::Snapshot> snapshots;  ///< of this episode (a reset drops them)
  std::uint64_t snapshots_taken = 0;
  Clock::time_point last_used;
  /// WebSockets open on it; shared with them, as they hold no reference to the session.
  std::shared_ptr<std::atomic<int>> clients = std::make_shared<std::atomic<int>>(0);
  // Realtime: the wall-clock time and tick it was last (re)started from.
  Clock::time_point realtime_origin;
  std::int64_t realtime_origin_tick = 0;

  sim::Session& session() { return episode->session(); }
  const sim::Session& session() const { return episode->session(); }
  /// The Gymnasium environment; null without a robot that can act.
  const tasks::Environment* environment() const { return episode->environment(); }

  /// A fresh episode of the same model (the lock held, or before anyone else has it).
  void start(std::shared_ptr<const scenario::Model> model) {
    episode = std::make_unique<episode::Episode>(
        std::move(model), static_cast<std::uint64_t>(seed),
        episode::Settings{std::nullopt, {}, true, sim::RecorderLimits{kMaxLiveRecordedBodies, recording_memory}, crowd_threads});
    events_reported = 0;
    realtime_origin = Clock::now();
    realtime_origin_tick = 0;
  }
};

/// Realtime sessions are stepped this often (wall clock), s.
inline constexpr double kRealtimeTick = 1.0 / 60.0;
/// A realtime session that falls behind catches up at most this much simulated time per tick (or two
/// ticks' worth at its factor, when more), s.
inline constexpr double kRealtimeMaxCatchUp = 0.5;
/// Largest realtime factor accepted.
inline constexpr double kMaxRealtimeFactor = 100.0;
/// Snapshots one session keeps at most.
inline constexpr std::size_t kMaxSnapshots = 32;

/// Answers with the session's lock held: at once when it is free, else on the worker pool, so that an
/// I/O thread never waits behind a long step (health checks and other sessions stay answered).
Response locked(std::shared_ptr<Live> live, std::function<Response(Live&)> work);

class Registry {
 public:
  explicit Registry(SessionLimits limits) : limits_(limits), ticker_([this](std::stop_token stop) { step_realtime(stop); }) {}
  ~Registry() {
    ticker_.request_stop();
    ticker_.join();
  }

  std::shared_ptr<Live> create(const std::string& scenario, std::shared_ptr<const scenario::Model> model, std::int64_t seed,
                               const std::string& mode, double realtime_factor, std::optional<nlohmann::json> controller, const std::string& owner) {
    std::lock_guard lock(mutex_);
    expire_idle();
    if (static_cast<int>(sessions_.size()) >= limits_.max_sessions) {
      throw core::Error(core::ErrorCode::unavailable,
                        "the server holds its maximum of " + std::to_string(limits_.max_sessions) + " sessions: delete one or retry later",
                        {{"max_sessions", limits_.max_sessions}, {"retry_after", kSessionRetryAfter}});
    }
    auto live = std::make_shared<Live>();
    live->id = core::unguessable_id('s');
    live->scenario = scenario;
    live->seed = seed;
    live->mode = mode;
    live->realtime_factor = realtime_factor;
    live->controller = std::move(controller);
    live->owner = owner;
    live->recording_memory = limits_.recording_memory;
    live->crowd_threads = limits_.crowd_threads;
    live->start(std::move(model));
    live->last_used = Clock::now();
    sessions_.emplace(live->id, live);
    return live;
  }

  /// The session as `caller` may see it: another owner's is absent (404), as an unknown one.
  std::shared_ptr<Live> find(const std::string& id, const Caller& caller) {
    std::lock_guard lock(mutex_);
    expire_idle();
    const auto found = sessions_.find(id);
    if (found == sessions_.end() || !visible_to(caller, found->second->owner)) {
      throw core::Error(core::ErrorCode::not_found, "no session '" + id + "'", {{"id", id}});
    }
    found->second->last_used = Clock::now();
    return found->second;
  }

  /// The session if it is still there, or null (for its WebSockets, which hold no reference to it).
  std::shared_ptr<Live> find_if_live(const std::string& id) {
    std::lock_guard lock(mutex_);
    const auto found = sessions_.find(id);
    if (found == sessions_.end()) return nullptr;
    found->second->last_used = Clock::now();
    return found->second;
  }

  void remove(const std::string& id, const Caller& caller) {
    std::lock_guard lock(mutex_);
    const auto found = sessions_.find(id);
    if (found == sessions_.end() || !visible_to(caller, found->second->owner)) {
      throw core::Error(core::ErrorCode::not_found, "no session '" + id + "'", {{"id", id}});
    }
    sessions_.erase(found);
  }

  std::vector<std::shared_ptr<Live>> all(const Caller& caller) {
    std::lock_guard lock(mutex_);
    expire_idle();
    std::vector<std::shared_ptr<Live>> list;
    for (const auto& [id, live] : sessions_) {
      if (visible_to(caller, live->owner)) list.push_back(live);
    }
    return list;
  }

 private:
  /// Idle sessions go (checked whenever the registry is used; the wall clock never enters a session);
  /// one with a WebSocket open is in use, even when its client is silent.
  void expire_idle() {
    const auto now = Clock::now();
    std::erase_if(sessions_, [&](const auto& entry) { return *entry.second->clients == 0 && now - entry.second->last_used > limits_.idle_timeout; });
  }

  /// Steps every realtime session to where the wall clock says it should be, kRealtimeTick apart. A
  /// session busy with a request is skipped this time; one that fell far behind skips ahead in wall
  /// time (it never steps more than kRealtimeMaxCatchUp at once).
  void step_realtime(std::stop_token stop) {
    auto next = Clock::now();
    while (!stop.stop_requested()) {
      next += std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kRealtimeTick));
      std::this_thread::sleep_until(next);
      std::vector<std::shared_ptr<Live>> realtime;
      {
        std::lock_guard lock(mutex_);
        for (const auto& [id, live] : sessions_) {
          if (live->mode == "realtime") realtime.push_back(live);
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

  SessionLimits limits_;
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Live>> sessions_;
  std::jthread ticker_;  ///< last: it uses everything above
};

}  // namespace hrisim::http
