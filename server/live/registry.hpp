#pragma once
// The live sessions of a server: created, found (as a caller may see them), expired when idle or
// unwatched, and — realtime ones — stepped by the wall clock on a ticker thread of its own. Every
// front end (the REST routes, the session WebSocket, bridges) reaches sessions through it.
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <stop_token>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/caller.hpp"
#include "live/limits.hpp"
#include "live/live_session.hpp"

namespace hrisim::live {

/// Restores and seeks (which simulate again, or far ahead) one owner may have queued or running at once.
/// Each may take a worker for a while, and the worker pool is every owner's: with one each, an owner's
/// seeks hold at most one worker, and other owners' steps go on on the others. Beyond it: refused
/// (unavailable), to be asked again kSimulationRetryAfter later.
inline constexpr int kMaxSimulationsPerOwner = 1;
inline constexpr int kSimulationRetryAfter = 1;

/// What a new session is made of (checked by the front end that asks for it).
struct NewSession {
  std::string scenario;
  std::shared_ptr<const scenario::Model> model;
  std::int64_t seed = 0;
  Mode mode = Mode::lockstep;
  double realtime_factor = 1.0;
  std::optional<nlohmann::json> controller;
  std::string owner;
  std::optional<std::chrono::seconds> unwatched_grace;
  std::string episode_id;  ///< a replay of this stored episode, with its run's settings below
  std::optional<double> time_limit;
  std::vector<std::pair<double, std::string>> requests;
  std::string scenario_sha256;  ///< of the scenario's document, as its snapshot files name it
};

/// At most `max_sessions` run at once; finished ones do not count, but the registry keeps at most that
/// many of them too (creating a session ends the least recently used unwatched finished ones beyond
/// it). A session goes when nobody used it for the idle timeout, or, with an unwatched grace, that
/// long after its last socket closed; one with a socket open stays.
class Registry {
 public:
  explicit Registry(SessionLimits limits) : limits_(limits), ticker_([this](std::stop_token stop) { step_realtime(stop); }) {}
  ~Registry() {
    ticker_.request_stop();
    ticker_.join();
  }
  Registry(const Registry&) = delete;
  Registry& operator=(const Registry&) = delete;

  /// Throws core::Error(unavailable) when `max_sessions` run already.
  std::shared_ptr<LiveSession> create(NewSession request);
  /// The session as `caller` may see it: another owner's is absent (not_found), as an unknown one.
  std::shared_ptr<LiveSession> find(const std::string& id, const core::Caller& caller);
  /// The session if it is still there, or null (for its sockets, which hold no reference to it).
  std::shared_ptr<LiveSession> find_if_live(const std::string& id);
  /// Whether the session is still there, without counting as a use (a socket watching for its end).
  bool contains(const std::string& id);
  void remove(const std::string& id, const core::Caller& caller);
  std::vector<std::shared_ptr<LiveSession>> all(const core::Caller& caller);
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
  std::map<std::string, std::shared_ptr<LiveSession>> sessions_;
  /// Places held per owner (admit_simulation); shared with the handles, which may outlive the registry.
  struct Simulations {
    std::mutex mutex;
    std::map<std::string, int> held;
  };
  std::shared_ptr<Simulations> simulations_ = std::make_shared<Simulations>();
  std::jthread ticker_;  ///< last: it uses everything above
};

}  // namespace hrisim::live
