#pragma once
// One episode of a scenario with a seed: the session, the Gymnasium environment of its scenario (the
// benchmark task, or the default navigation view; none without a robot that can act) and the recording
// its metrics are computed from. Every driver goes through it, so a scenario behaves the same in a
// session stepped by a client, a realtime session, a run and a replay:
//
//   tick():  begin an env step when none is under way (the task's hooks, e.g. the person walks on)
//            → Session::step() → the env step's after-tick bookkeeping → at its last tick its reward
//            (and the task's ending, which ends the episode) → the recording's sample.
//   step(action, n): n env steps, the action given at the first; each is its frame skip of ticks.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "metrics/recording.hpp"
#include "sim/episode_recorder.hpp"
#include "sim/session.hpp"
#include "tasks/environment.hpp"

namespace hrisim::episode {

struct Settings {
  std::optional<double> time_limit;  ///< s of simulation time; the scenario's own when empty
  /// Scripted robot requests: the robot under test asks for routine `second` at time `first`.
  std::vector<std::pair<double, std::string>> requests;
  bool record = true;  ///< false: no recording (benchmarks of the simulation alone)
  sim::RecorderLimits recording;
};

class Episode {
 public:
  /// Throws core::Error(bad_request) for a scripted request the scenario cannot make, and what the
  /// benchmark task throws when it cannot set its episode up.
  Episode(std::shared_ptr<const scenario::Model> model, std::uint64_t seed, Settings settings = {});
  Episode(const Episode&) = delete;
  Episode& operator=(const Episode&) = delete;

  /// Gymnasium's step, `n` times (without an environment: n ticks): `action` is given at the first.
  /// Returns the rewards of the env steps summed; stops early once the episode is over. Throws
  /// core::Error(bad_request) for an action of the wrong length or not finite (pointer "/action/i").
  double step(const std::optional<std::vector<double>>& action = std::nullopt, std::int64_t n = 1);
  /// One tick as a clock gives it (realtime sessions, runs): an env step without a new action begins
  /// whenever the last one is done.
  void tick();
  /// Ticks until the episode is over; false when `cancel` was set first. `after_tick` sees every tick.
  bool run(const std::atomic<bool>* cancel = nullptr, const std::function<void(const Episode&)>& after_tick = nullptr);

  /// The session finished: the scenario's end, its time limit, or the benchmark task's ending.
  bool over() const { return session_->state().finished; }
  sim::Session& session() { return *session_; }
  const sim::Session& session() const { return *session_; }
  /// Null for a scenario without a robot that can act.
  tasks::Environment* environment() { return environment_ ? &*environment_ : nullptr; }
  const tasks::Environment* environment() const { return environment_ ? &*environment_ : nullptr; }
  /// Null when the settings asked for no recording.
  const sim::EpisodeRecorder* recorder() const { return recorder_ ? &*recorder_ : nullptr; }
  /// Env steps completed.
  std::int64_t env_steps() const { return env_steps_; }
  /// The rewards of the env steps completed, summed.
  double total_reward() const { return reward_.total; }

  /// What the metrics are computed from: the recording (the settings must have asked for one) with the
  /// rewards; `termination` replaces the session's own (e.g. "running" for a session not yet over).
  metrics::Recording recording(std::string termination = "") const;

 private:
  /// One tick of the env step under way (or a bare tick without an environment).
  void advance();
  /// Ends the env step under way: its reward is added, and the task's ending ends the episode.
  double end_step();

  std::unique_ptr<sim::Session> session_;
  std::optional<tasks::Environment> environment_;
  std::optional<sim::EpisodeRecorder> recorder_;
  int ticks_left_ = 0;  ///< of the env step under way; 0 between env steps
  std::int64_t env_steps_ = 0;
  tasks::Reward reward_;  ///< summed over the env steps, term by term
  double last_reward_ = 0.0;  ///< of the last env step
};

}  // namespace hrisim::episode
