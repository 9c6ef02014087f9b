#pragma once
// One episode of a scenario with a seed: the session, the Gymnasium environment of its scenario (the
// benchmark task, or the default navigation task; none without a robot that can act) and the recording
// its metrics are computed from. Every driver goes through it, so a scenario behaves the same in a
// session stepped by a client, a realtime session, a run and a replay:
//
//   tick():  begin an env step when none is under way (the task's hooks, e.g. the person walks on)
//            → Session::tick() → the env step's after-tick bookkeeping → at its last tick its reward
//            (and the task's ending, which ends the episode) → the recording's sample.
//   step(action, n): n env steps, the action given at the first; each is its frame skip of ticks.
//
// What drives an episode from outside — env steps, ticks, and inputs such as commands and placements —
// is kept in its input log. A snapshot is the log so far and the state's hash; restoring it gives the
// same inputs to a fresh episode of the same scenario and seed, which (being deterministic) reaches
// the same state bit for bit, physics included: the Bullet world's contact caches are history that no
// copy of the state would carry. Restoring costs re-simulating up to the snapshot's tick.
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/memory_budget.hpp"
#include "episode/inputs.hpp"
#include "metrics/recording.hpp"
#include "sim/episode_recorder.hpp"
#include "sim/session.hpp"
#include "tasks/environment.hpp"

namespace hrisim::episode {

/// A live session's episode keeps a checkpoint (a copy of the session, the task's state with it, and its
/// place in the input log) about this often, simulated seconds: a seek back simulates again at most this much
/// from the checkpoint before it (the elevator: 600 ticks, ≈ 25 ms) instead of everything from tick 0,
/// while copying the state that rarely costs well under 1% of stepping (bench/RESULTS.md, seek_bench).
/// The interval at which a physics world with movable objects is built again from the state, so that
/// such scenarios can be copied exactly then (sim::kPhysicsRebuildInterval).
inline constexpr double kCheckpointInterval = sim::kPhysicsRebuildInterval;
/// Bytes of checkpoints one episode keeps at most (estimated from the state's data; the elevator's are
/// about 130 KiB each, so about 80 minutes of it fit). Past it, every
/// other checkpoint goes and the interval doubles: memory stays bounded, and a seek back simulates
/// again at most twice the episode's length over the checkpoints that fit (docs/limits.md).
inline constexpr std::size_t kMaxCheckpointBytes = std::size_t{64} << 20;

/// When an episode keeps checkpoints and within what memory.
struct CheckpointLimits {
  std::optional<double> every;  ///< simulated seconds between checkpoints; none: no checkpoints (runs)
  std::size_t max_bytes = kMaxCheckpointBytes;
  core::MemoryBudget* memory = nullptr;  ///< shared with others (the server's), when given
};

struct Settings {
  std::optional<double> time_limit;  ///< s of simulation time; the scenario's own when empty
  /// Scripted robot requests: the robot under test asks for routine `second` at time `first`.
  std::vector<std::pair<double, std::string>> requests;
  bool record = true;  ///< false: no recording (benchmarks of the simulation alone)
  sim::RecorderLimits recording;
  unsigned crowd_threads = 1;  ///< Session::set_crowd_threads: the same trajectory for any count
  CheckpointLimits checkpoints = {};  ///< none by default: only seeking needs them
};

class Episode {
 public:
  /// A point of an episode to come back to (Episode::restore).
  struct Snapshot {
    struct Entry {
      enum class Kind { input, step, ticks };
      Kind kind = Kind::ticks;
      std::int64_t tick = 0;                      ///< the session's tick when it was given or began
      std::optional<Input> input;                 ///< input: what was given
      std::optional<std::vector<double>> action;  ///< step: the action of its first env step
      std::int64_t count = 0;                     ///< step: env steps done; ticks: how many
      /// Its number among the entries of this episode and of the episodes rewound or restored from it
      /// (0: read from a file): a snapshot whose entries the episode still has continues it.
      std::uint64_t serial = 0;
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
  /// Everything that drove the episode so far.
  const std::vector<Snapshot::Entry>& input_log() const { return log_; }

  /// This point of the episode.
  Snapshot snapshot() const;
  /// The episode at the snapshot's moment, bit for bit. A snapshot of this episode's own past (its
  /// entries are still this episode's) is a rewind to its tick: from the checkpoint before it, and the
  /// returned episode takes this one's recording, as rewind() does (go on with it, not with this).
  /// Any other — an earlier branch, a file (`foreign`) — drives a fresh episode of the same scenario,
  /// seed and settings by its log, checked by each entry's tick and the snapshot's hash:
  /// core::Error(internal) when that fails, or core::Error(conflict) for a file, which another build of
  /// hrisim may have simulated differently.
  std::unique_ptr<Episode> restore(const Snapshot& snapshot, bool foreign = false);
  /// This episode as it was at `tick` (at most the present tick), with the inputs given at that tick:
  /// the latest checkpoint at or before `tick` (or a fresh episode of the same scenario, seed and
  /// settings) given this one's inputs from there until then. With a benchmark task it stops at the
  /// end of the env step that reaches `tick`. The returned episode takes this one's recording (the
  /// samples after `tick` forgotten) and its checkpoints up to `tick`: go on with it, not with this.
  std::unique_ptr<Episode> rewind(std::int64_t tick);
  /// Ticks the rewind that made this episode simulated again (0 for an episode not made by one).
  std::int64_t ticks_simulated_again() const { return ticks_simulated_again_; }
  /// Checkpoints kept, and their estimated bytes.
  std::size_t checkpoints() const { return checkpoints_.size(); }
  std::size_t checkpoint_bytes() const { return checkpoint_bytes_; }

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
  /// The episode at a tick between env steps, and where its input log was then: entries before
  /// `log_entry` all given, and the first `log_done` env steps or ticks of that one.
  struct Checkpoint {
    sim::Session::Copy session;  ///< the task's bookkeeping included (sim::TaskState): the task itself is shared
    std::int64_t tick = 0;
    std::int64_t env_steps = 0;
    tasks::Reward reward;
    double last_reward = 0.0;
    std::size_t log_entry = 0;
    std::int64_t log_done = 0;
    std::size_t bytes = 0;  ///< estimated
  };

  /// The episode `from` was at `checkpoint`, without a recording (rewind gives it one).
  Episode(const Episode& from, const Checkpoint& checkpoint);
  /// Keeps a checkpoint when one is due, the episode is between env steps and its session can be copied.
  void keep_checkpoint();
  /// Takes the checkpoint within the limits: every other one goes (and the interval doubles) while it
  /// does not fit; false when it does not fit even alone.
  bool fit(std::shared_ptr<const Checkpoint> checkpoint);
  /// Gives this episode `from`'s log from where it is (`entry`, `done` of it) until `tick` is reached.
  void replay_until(const Episode& from, std::size_t entry, std::int64_t done, std::int64_t tick);

  /// One env step (without an environment: one tick), `action` given first; its reward.
  double env_step(const std::optional<std::vector<double>>& action);
  /// One tick as a clock gives it, not logged.
  void clock_tick();
  /// One tick of the env step under way (or a bare tick without an environment).
  void advance();
  /// Ends the env step under way: its reward is added, and the task's ending ends the episode.
  double end_step();

  /// Adds ticks to the log (runs of ticks are one entry).
  void log_ticks(std::int64_t count);
  /// Adds an entry to the log with the next serial (or `serial`, an entry given again by a rewind).
  void log(Snapshot::Entry entry, std::uint64_t serial = 0);
  /// Whether the snapshot's entries are this episode's, each as far as it went then.
  bool continues(const Snapshot& snapshot) const;
  /// Gives a log entry again (restoring).
  void replay(const Snapshot::Entry& entry);

  std::shared_ptr<const scenario::Model> model_;
  std::uint64_t seed_;
  Settings settings_;
  std::vector<Snapshot::Entry> log_;
  /// The last serial given to an entry; shared with the episodes rewound or restored from this one.
  std::shared_ptr<std::uint64_t> last_serial_ = std::make_shared<std::uint64_t>(0);
  std::unique_ptr<sim::Session> session_;
  std::optional<tasks::Environment> environment_;
  std::optional<sim::EpisodeRecorder> recorder_;
  int ticks_left_ = 0;  ///< of the env step under way; 0 between env steps
  std::int64_t env_steps_ = 0;
  tasks::Reward reward_;  ///< summed over the env steps, term by term
  double last_reward_ = 0.0;  ///< of the last env step
  std::vector<std::shared_ptr<const Checkpoint>> checkpoints_;  ///< in tick order; shared with rewound episodes
  std::int64_t checkpoint_every_ = 0;  ///< ticks; 0: none kept
  std::int64_t next_checkpoint_ = 0;   ///< the tick from which the next is due
  std::size_t checkpoint_bytes_ = 0;
  core::MemoryBudget::Lease checkpoint_memory_;
  std::int64_t ticks_simulated_again_ = 0;
};

}  // namespace hrisim::episode
