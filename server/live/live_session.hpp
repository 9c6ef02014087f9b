#pragma once
// A live session: what the server keeps for one (its episode, mode, snapshots, who watches it),
// whichever front end drives it — the REST routes, the session WebSocket, a bridge.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/memory_budget.hpp"
#include "episode/episode.hpp"

namespace hrisim::live {

using Clock = std::chrono::steady_clock;

/// Who steps a session: its clients (lockstep), or the server by the wall clock (realtime).
enum class Mode { lockstep, realtime };

constexpr std::string_view to_string(Mode mode) { return mode == Mode::realtime ? "realtime" : "lockstep"; }
constexpr std::optional<Mode> parse_mode(std::string_view text) {
  if (text == "lockstep") return Mode::lockstep;
  if (text == "realtime") return Mode::realtime;
  return std::nullopt;
}

/// A live session records at most this many bodies (people and robot, summed over its steps) for its
/// metrics on demand: packed, 120–250 MB (memory_bench: 15–32 B a body), 5 hours of the elevator's
/// six people and HSR at 60 Hz, two minutes of a thousand people. Its metrics then cover the steps
/// up to `recorded_until_tick`.
inline constexpr std::size_t kMaxLiveRecordedBodies = 8'000'000;

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

struct LiveSession {
  std::string id, scenario;
  std::string owner;  ///< who created it (the token's name); empty without owners
  std::int64_t seed = 0;
  Mode mode = Mode::lockstep;
  double realtime_factor = 1.0;   ///< realtime: simulated seconds per wall-clock second
  std::optional<nlohmann::json> controller;  ///< replaced the robot under test's, when given
  /// A replay of a stored episode: its id; its run's time limit and scripted requests hold here too.
  std::string episode_id;
  std::optional<double> time_limit;
  std::vector<std::pair<double, std::string>> requests;
  std::string scenario_sha256;  ///< of the scenario's document: a snapshot file starts only on the same scenario
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
  /// Sockets open on it (of any front end); shared with them, as they hold no reference to the session.
  std::shared_ptr<std::atomic<int>> clients = std::make_shared<std::atomic<int>>(0);
  // Realtime: the wall-clock time and tick it was last (re)started from.
  Clock::time_point realtime_origin;
  std::int64_t realtime_origin_tick = 0;

  sim::Session& session() { return episode->session(); }
  const sim::Session& session() const { return episode->session(); }
  /// The Gymnasium environment; null without a robot that can act.
  const tasks::Environment* environment() const { return episode->environment(); }

  /// A fresh episode of `model` with `seed` and this session's settings, not yet its own.
  std::unique_ptr<episode::Episode> new_episode(std::shared_ptr<const scenario::Model> model, std::int64_t with_seed) const {
    return std::make_unique<episode::Episode>(
        std::move(model), static_cast<std::uint64_t>(with_seed),
        episode::Settings{time_limit, requests, true, sim::RecorderLimits{kMaxLiveRecordedBodies, recording_memory}, crowd_threads,
                          episode::CheckpointLimits{episode::kCheckpointInterval, episode::kMaxCheckpointBytes, recording_memory}});
  }
  /// A fresh episode of the same model (the lock held, or before anyone else has it).
  void start(std::shared_ptr<const scenario::Model> model) {
    episode = new_episode(std::move(model), seed);
    events_reported = 0;
    realtime_origin = Clock::now();
    realtime_origin_tick = 0;
  }
};

}  // namespace hrisim::live
