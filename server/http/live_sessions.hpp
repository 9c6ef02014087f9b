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
  /// A replay of a stored episode: its id; its run's time limit and scripted requests hold here too.
  std::string episode_id;
  std::optional<double> time_limit;
  std::vector<std::pair<double, std::string>> requests;
  std::mutex mutex;  ///< one request at a time works on the session
  std::unique_ptr<episode::Episode> episode;
  core::MemoryBudget* recording_memory = nullptr;  ///< shared by every recording of the server
  unsigned crowd_threads = 1;  ///< threads computing the crowd's velocities (`--crowd-threads`)
  std::size_t events_reported = 0;  ///< events before this index were in a step reply already
  std::uint64_t generation = 0;     ///< counts resets and restores, so that viewers notice a fresh start
  std::map<std::string, episode::Episode::Snapshot> snapshots;  ///< of this episode (a reset drops them)
  std::uint64_t snapshots_taken = 0;
  std::atomic<Clock::time_point> last_used;  ///< by a request, a WebSocket's message or push, or its close
  /// Ends the session this long after its last WebSocket closed (the browser asks for it, so that a
  /// closed tab's session goes); none: the idle timeout alone.
  std::optional<std::chrono::seconds> unwatched_grace;
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
        episode::Settings{time_limit, requests, true, sim::RecorderLimits{kMaxLiveRecordedBodies, recording_memory}, crowd_threads,
                          episode::CheckpointLimits{episode::kCheckpointInterval, episode::kMaxCheckpointBytes, recording_memory}});
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
/// Longest unwatched grace a session may ask for, s.
inline constexpr std::chrono::seconds kMaxUnwatchedGrace{3600};
/// Snapshots one session keeps at most.
inline constexpr std::size_t kMaxSnapshots = 32;

/// Restores and seeks (which simulate again, or far ahead) one owner may have queued or running at once.
/// Each may take a worker for a while, and the worker pool is every owner's: with one each, an owner's
/// seeks hold at most one worker, and other owners' steps go on on the others. Beyond it: 503 with
/// Retry-After: kSimulationRetryAfter.
inline constexpr int kMaxSimulationsPerOwner = 1;
inline constexpr int kSimulationRetryAfter = 1;

/// Answers with the session's lock held: at once when it is free, else on the worker pool, so that an
/// I/O thread never waits behind a long step (health checks and other sessions stay answered).
Response locked(std::shared_ptr<Live> live, std::function<Response(Live&)> work);

/// Does a restore's or seek's `work` on the worker pool holding `place` (Registry::admit_simulation),
/// given back as soon as the work ends, before its answer is sent: the owner's next one may follow it
/// at once instead of finding the place still taken.
Response simulation_later(std::shared_ptr<void> place, std::function<Response()> work);

/// What a new session is made of (POST /api/v1/sessions, checked).
struct NewSession {
  std::string scenario;
  std::shared_ptr<const scenario::Model> model;
  std::int64_t seed = 0;
  std::string mode = "lockstep";
  double realtime_factor = 1.0;
  std::optional<nlohmann::json> controller;
  std::string owner;
  std::optional<std::chrono::seconds> unwatched_grace;
  std::string episode_id;  ///< a replay of this stored episode, with its run's settings below
  std::optional<double> time_limit;
  std::vector<std::pair<double, std::string>> requests;
};

/// The live sessions. At most `max_sessions` run at once; finished ones do not count, but the registry
/// keeps at most that many of them too (creating a session ends the least recently used unwatched
/// finished ones beyond it). A session goes when nobody used it for the idle timeout, or, with an
/// unwatched grace, that long after its last WebSocket closed; one with a WebSocket open stays.
class Registry {
 public:
  explicit Registry(SessionLimits limits) : limits_(limits), ticker_([this](std::stop_token stop) { step_realtime(stop); }) {}
  ~Registry() {
    ticker_.request_stop();
    ticker_.join();
  }

  /// Throws core::Error(unavailable) when `max_sessions` run already.
  std::shared_ptr<Live> create(NewSession request);
  /// The session as `caller` may see it: another owner's is absent (404), as an unknown one.
  std::shared_ptr<Live> find(const std::string& id, const Caller& caller);
  /// The session if it is still there, or null (for its WebSockets, which hold no reference to it).
  std::shared_ptr<Live> find_if_live(const std::string& id);
  /// Whether the session is still there, without counting as a use (a socket watching for its end).
  bool contains(const std::string& id);
  void remove(const std::string& id, const Caller& caller);
  std::vector<std::shared_ptr<Live>> all(const Caller& caller);
  /// A place for one of `owner`'s restores or seeks, given back when the returned handle goes (keep it
  /// until the work is done). Throws core::Error(unavailable) when the owner holds
  /// kMaxSimulationsPerOwner places already.
  std::shared_ptr<void> admit_simulation(const std::string& owner);

 private:
  /// Idle and unwatched sessions go (checked whenever the registry is used, and every second by the
  /// ticker; the wall clock never enters a session).
  void expire_idle();
  /// Steps every realtime session to where the wall clock says it should be, kRealtimeTick apart.
  void step_realtime(std::stop_token stop);

  SessionLimits limits_;
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Live>> sessions_;
  /// Places held per owner (admit_simulation); shared with the handles, which may outlive the registry.
  struct Simulations {
    std::mutex mutex;
    std::map<std::string, int> held;
  };
  std::shared_ptr<Simulations> simulations_ = std::make_shared<Simulations>();
  std::jthread ticker_;  ///< last: it uses everything above
};

}  // namespace hrisim::http
