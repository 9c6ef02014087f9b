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
//
// What drives an episode from outside — env steps, ticks, and inputs such as commands and placements —
// is kept in its input log. A snapshot is the log so far and the state's hash; restoring it gives the
// same inputs to a fresh episode of the same scenario and seed, which (being deterministic) reaches
// the same state bit for bit, physics included: the Bullet world's contact caches are history that no
// copy of the state would carry. Restoring costs re-simulating up to the snapshot's tick.
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
  unsigned crowd_threads = 1;  ///< Session::set_crowd_threads: the same trajectory for any count
};

class Episode {
 public:
  /// An input from outside (a command, a placement), given to the session between ticks.
  using Input = std::function<void(sim::Session&)>;

  /// A point of an episode to come back to (Episode::restore).
  struct Snapshot {
    struct Entry {
      enum class Kind { input, step, ticks };
      Kind kind = Kind::ticks;
      Input input;                                ///< input: what was given
      std::optional<std::vector<double>> action;  ///< step: the action of its first env step
      std::int64_t count = 0;                     ///< step: env steps asked for; ticks: how many
    };
    std::vector<Entry> log;  ///< everything that drove the episode up to here
    std::int64_t tick = 0;
    std::uint64_t state_hash = 0;
  };

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
  /// Gives an input to the session now and keeps it in the log. What it throws, it throws before
  /// changing anything (check first), and then it is not kept.
  void give(const Input& input);

  /// This point of the episode.
  Snapshot snapshot() const;
  /// A fresh episode of the same scenario, seed and settings driven by the snapshot's log: the state
  /// the snapshot was taken in, bit for bit (checked by its hash; core::Error(internal) otherwise).
  std::unique_ptr<Episode> restore(const Snapshot& snapshot) const;
  /// This episode as it was at `tick` (at most the present tick), with the inputs given at that tick:
  /// a fresh episode of the same scenario, seed and settings given this one's inputs until then. With
  /// a benchmark task it stops at the end of the env step that reaches `tick`.
  std::unique_ptr<Episode> rewind(std::int64_t tick) const;

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

  /// Adds ticks to the log (runs of ticks are one entry).
  void log_ticks(std::int64_t count);
  /// Gives a log entry again (restoring).
  void replay(const Snapshot::Entry& entry);

  std::shared_ptr<const scenario::Model> model_;
  std::uint64_t seed_;
  Settings settings_;
  std::vector<Snapshot::Entry> log_;
  std::unique_ptr<sim::Session> session_;
  std::optional<tasks::Environment> environment_;
  std::optional<sim::EpisodeRecorder> recorder_;
  int ticks_left_ = 0;  ///< of the env step under way; 0 between env steps
  std::int64_t env_steps_ = 0;
  tasks::Reward reward_;  ///< summed over the env steps, term by term
  double last_reward_ = 0.0;  ///< of the last env step
};

}  // namespace hrisim::episode
