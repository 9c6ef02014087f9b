#include "episode/episode.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "core/error.hpp"
#include "tasks/task_support.hpp"

namespace hrisim::episode {
namespace {

/// A checkpoint's heap per byte of data its state hash reads: the containers' headers and spare
/// capacity, and what the hash leaves out (sensors' beam tables, the robots' planners). Measured on the
/// bundled scenarios: 2.1 (queue) to 7.6 (the elevator at tick 100,000) bytes (bench/RESULTS.md).
constexpr std::size_t kCheckpointBytesPerStateByte = 8;

int robot_under_test(const scenario::Model& model) {
  for (std::size_t a = 0; a < model.agents.size(); ++a) {
    if (model.agents[a].kind == scenario::AgentKind::robot) return static_cast<int>(a);
  }
  return -1;
}

/// Adds a step's reward to the sums, term by term (in the order the terms first came).
void add_to(tasks::Reward& sum, const tasks::Reward& reward) {
  sum.total += reward.total;
  for (const auto& term : reward.terms) {
    const std::string& name = term.first;
    const double value = term.second;
    auto found = std::find_if(sum.terms.begin(), sum.terms.end(), [&](const auto& known) { return known.first == name; });
    if (found == sum.terms.end()) {
      sum.terms.emplace_back(name, value);
    } else {
      found->second += value;
    }
  }
}

}  // namespace

Episode::Episode(std::shared_ptr<const scenario::Model> model, std::uint64_t seed, Settings settings)
    : model_(model),
      seed_(seed),
      settings_(settings),
      session_(std::make_unique<sim::Session>(std::move(model), seed)),
      checkpoint_memory_(settings.checkpoints.memory) {
  const scenario::Model& scenario = session_->model();
  if (settings.checkpoints.every) checkpoint_every_ = std::max<std::int64_t>(1, std::llround(*settings.checkpoints.every / scenario.dt));
  next_checkpoint_ = checkpoint_every_;
  if (settings.time_limit) session_->set_time_limit(*settings.time_limit);
  session_->set_crowd_threads(settings.crowd_threads);
  for (const auto& [time, name] : settings.requests) {
    const int task = scenario.find_routine(name);
    if (task < 0) throw core::Error(core::ErrorCode::bad_request, "the scenario has no task '" + name + "' to request");
    const int robot = robot_under_test(scenario);
    if (robot < 0) throw core::Error(core::ErrorCode::bad_request, "the scenario has no robot to make the request");
    session_->schedule_request(time, session_->agent_id(scenario.agents[robot].id), task);
  }
  try {
    environment_.emplace(*session_);  // before recording: a benchmark task places its human at tick 0
  } catch (const core::Error&) {
    // No robot to observe, or none that can act: the episode has no environment. A benchmark task
    // that cannot set its episode up is the caller's error.
    if (scenario.task) throw;
  }
  if (environment_ && environment_->terminated(*session_)) session_->end_by_task();
  if (settings.record) recorder_.emplace(*session_, settings.recording);
}

double Episode::step(const std::optional<std::vector<double>>& action, std::int64_t n) {
  if (action && environment_) tasks::check_action(*action, static_cast<std::size_t>(environment_->action_space().shape.at(0)));
  // Env steps without a new action go on the last run of env steps: replayed, it gives them the same
  // way (no action after its first), and a client stepping one at a time keeps the log short.
  if (action || log_.empty() || log_.back().kind != Snapshot::Entry::Kind::step) {
    log({Snapshot::Entry::Kind::step, session_->state().tick, std::nullopt, action, 0});
  }
  double reward = 0.0;
  for (std::int64_t i = 0; i < n && !over(); ++i) {
    ++log_.back().count;
    reward += env_step(i == 0 ? action : std::nullopt);
    keep_checkpoint();
  }
  return reward;
}

double Episode::env_step(const std::optional<std::vector<double>>& action) {
  if (!environment_) {
    advance();
    return 0.0;
  }
  double reward = 0.0;
  if (ticks_left_ > 0) reward += end_step();  // a clock's env step under way ends here
  ticks_left_ = environment_->begin_step(*session_, action);
  if (ticks_left_ <= 0) return reward + end_step();
  const std::int64_t before = env_steps_;
  while (env_steps_ == before) advance();
  return reward + last_reward_;
}

void Episode::tick() {
  if (over()) return;
  log_ticks(1);
  clock_tick();
  keep_checkpoint();
}

void Episode::clock_tick() {
  if (environment_ && ticks_left_ <= 0) {
    ticks_left_ = environment_->begin_step(*session_, std::nullopt);
    if (ticks_left_ <= 0) {
      end_step();
      return;
    }
  }
  advance();
}

bool Episode::run(const std::atomic<bool>* cancel, const std::function<void(const Episode&)>& after_tick) {
  while (!over()) {
    if (cancel && cancel->load(std::memory_order_relaxed)) return false;
    const std::int64_t before = session_->state().tick;
    tick();
    // The last call may find the scenario over without a tick (its last choreography step done).
    if (after_tick && session_->state().tick != before) after_tick(*this);
  }
  return true;
}

void Episode::give(const Input& input) {
  give_input(*session_, input);
  log({Snapshot::Entry::Kind::input, session_->state().tick, input, std::nullopt, 0});
}

void Episode::log_ticks(std::int64_t count) {
  if (!log_.empty() && log_.back().kind == Snapshot::Entry::Kind::ticks) {
    log_.back().count += count;
  } else {
    log({Snapshot::Entry::Kind::ticks, session_->state().tick, std::nullopt, std::nullopt, count});
  }
}

void Episode::log(Snapshot::Entry entry, std::uint64_t serial) {
  entry.serial = serial != 0 ? serial : ++*last_serial_;
  log_.push_back(std::move(entry));
}

bool Episode::continues(const Snapshot& snapshot) const {
  if (snapshot.log.empty() || snapshot.log.size() > log_.size()) return false;
  for (std::size_t e = 0; e < snapshot.log.size(); ++e) {
    const Snapshot::Entry& then = snapshot.log[e];
    const Snapshot::Entry& now = log_[e];
    const bool last = e + 1 == snapshot.log.size();
    if (then.serial == 0 || then.serial != now.serial || then.tick != now.tick || (last ? now.count < then.count : now.count != then.count)) {
      return false;
    }
  }
  return true;
}

Episode::Snapshot Episode::snapshot() const { return {log_, session_->state().tick, session_->state_hash()}; }

std::unique_ptr<Episode> Episode::restore(const Snapshot& snapshot, bool foreign) {
  if (!foreign && continues(snapshot)) {
    std::unique_ptr<Episode> rewound = rewind(snapshot.tick);
    if (rewound->session().state_hash() != snapshot.state_hash) {
      throw core::Error(core::ErrorCode::internal, "going back to the snapshot of tick " + std::to_string(snapshot.tick) +
                                                       " did not reach its state: the simulation was not deterministic here");
    }
    return rewound;
  }
  const auto refuse = [&](const std::string& what, nlohmann::json details) {
    if (!foreign) throw core::Error(core::ErrorCode::internal, what + ": the simulation was not deterministic here");
    throw core::Error(core::ErrorCode::conflict,
                      what + ": the snapshot was changed, or this build of hrisim simulates the scenario differently from the one that took it",
                      std::move(details));
  };
  auto restored = std::make_unique<Episode>(model_, seed_, settings_);
  restored->last_serial_ = last_serial_;  // its entries are numbered apart from this one's
  for (std::size_t e = 0; e < snapshot.log.size(); ++e) {
    const std::int64_t reached = restored->session().state().tick;
    if (reached != snapshot.log[e].tick) {
      refuse("input " + std::to_string(e) + " of the snapshot was given at tick " + std::to_string(snapshot.log[e].tick) + ", replayed at tick " +
                 std::to_string(reached),
             {{"input", e}});
    }
    restored->replay(snapshot.log[e]);
  }
  if (restored->session().state_hash() != snapshot.state_hash) {
    refuse("restoring the snapshot of tick " + std::to_string(snapshot.tick) + " did not reach the state it names", {{"state_hash", true}});
  }
  return restored;
}

std::unique_ptr<Episode> Episode::rewind(std::int64_t tick) {
  const auto after = std::upper_bound(checkpoints_.begin(), checkpoints_.end(), tick,
                                      [](std::int64_t t, const std::shared_ptr<const Checkpoint>& checkpoint) { return t < checkpoint->tick; });
  std::unique_ptr<Episode> rewound;
  std::size_t entry = 0;
  std::int64_t done = 0;
  if (after == checkpoints_.begin()) {
    rewound = std::make_unique<Episode>(model_, seed_, settings_);
    rewound->last_serial_ = last_serial_;
    rewound->recorder_.reset();  // it takes this one's, below
  } else {
    const Checkpoint& from = **std::prev(after);
    rewound.reset(new Episode(*this, from));
    entry = from.log_entry;
    done = from.log_done;
    rewound->log_.assign(log_.begin(), log_.begin() + static_cast<std::ptrdiff_t>(entry) + 1);
    rewound->log_.back().count = done;
  }
  rewound->checkpoint_every_ = checkpoint_every_;
  for (auto kept = checkpoints_.begin(); kept != after && rewound->fit(*kept); ++kept) {
  }
  rewound->next_checkpoint_ = (rewound->checkpoints_.empty() ? 0 : rewound->checkpoints_.back()->tick) + rewound->checkpoint_every_;
  const std::int64_t start = rewound->session().state().tick;
  rewound->replay_until(*this, entry, done, tick);
  rewound->ticks_simulated_again_ = rewound->session().state().tick - start;
  if (recorder_) {
    // The recording up to the tick is the rewound episode's, bit for bit: it is taken, not made again.
    recorder_->forget_after(rewound->session().state().tick);
    rewound->recorder_ = std::move(recorder_);
    recorder_.reset();
  }
  return rewound;
}

void Episode::replay_until(const Episode& from, std::size_t entry, std::int64_t done, std::int64_t tick) {
  const auto at_tick = [&] { return session_->state().tick >= tick; };
  for (std::size_t e = entry; e < from.log_.size(); ++e, done = 0) {
    const Snapshot::Entry& given = from.log_[e];
    if (given.kind == Snapshot::Entry::Kind::input) {
      give(*given.input);
      log_.back().serial = given.serial;  // the same entry again: snapshots that hold it still continue this
      continue;
    }
    if (done == 0) log({given.kind, session_->state().tick, std::nullopt, given.action, 0}, given.serial);
    for (; done < given.count && !at_tick() && !over(); ++done) {
      ++log_.back().count;
      // One env step at a time, the action at the first: the same ticks as step(action, count).
      if (given.kind == Snapshot::Entry::Kind::step) {
        env_step(done == 0 ? given.action : std::nullopt);
      } else {
        clock_tick();
      }
      keep_checkpoint();
    }
    if (done < given.count && at_tick()) return;  // cut short: what follows was given after `tick`
  }
}

Episode::Episode(const Episode& from, const Checkpoint& checkpoint)
    : model_(from.model_),
      seed_(from.seed_),
      settings_(from.settings_),
      last_serial_(from.last_serial_),
      session_(std::make_unique<sim::Session>(from.model_, checkpoint.session, from.session().state().events)),
      environment_(from.environment_),  // the same task: its state is in the session copy
      env_steps_(checkpoint.env_steps),
      reward_(checkpoint.reward),
      last_reward_(checkpoint.last_reward),
      checkpoint_memory_(from.settings_.checkpoints.memory) {
  session_->set_crowd_threads(settings_.crowd_threads);
}

void Episode::keep_checkpoint() {
  const std::int64_t tick = session_->state().tick;
  if (checkpoint_every_ == 0 || tick < next_checkpoint_ || (environment_ && ticks_left_ > 0)) return;
  std::optional<sim::Session::Copy> copy = session_->copy();
  if (!copy) return;  // Bullet's world holds history now: tried again after the next env step (at the latest when it is built again)
  auto checkpoint = std::make_shared<Checkpoint>(
      Checkpoint{std::move(*copy), tick, env_steps_, reward_, last_reward_, log_.size() - 1, log_.back().count, 0});
  checkpoint->bytes = kCheckpointBytesPerStateByte * sim::state_data_bytes(checkpoint->session.state) + sizeof(Checkpoint);
  fit(std::move(checkpoint));
  next_checkpoint_ = tick + checkpoint_every_;
}

bool Episode::fit(std::shared_ptr<const Checkpoint> checkpoint) {
  while (checkpoint_bytes_ + checkpoint->bytes > settings_.checkpoints.max_bytes || !checkpoint_memory_.grow(checkpoint->bytes)) {
    if (checkpoints_.empty()) return false;
    // Every other one goes, from the first: those left are twice as far apart, and so is the next.
    std::vector<std::shared_ptr<const Checkpoint>> kept;
    for (std::size_t c = 0; c < checkpoints_.size(); ++c) {
      if (c % 2 == 1) {
        kept.push_back(checkpoints_[c]);
        continue;
      }
      checkpoint_bytes_ -= checkpoints_[c]->bytes;
      checkpoint_memory_.shrink(checkpoints_[c]->bytes);
    }
    checkpoints_ = std::move(kept);
    checkpoint_every_ *= 2;
  }
  checkpoint_bytes_ += checkpoint->bytes;
  checkpoints_.push_back(std::move(checkpoint));
  return true;
}

void Episode::replay(const Snapshot::Entry& entry) {
  switch (entry.kind) {
    case Snapshot::Entry::Kind::input:
      give(*entry.input);
      return;
    case Snapshot::Entry::Kind::step:
      step(entry.action, entry.count);
      return;
    case Snapshot::Entry::Kind::ticks:
      for (std::int64_t t = 0; t < entry.count && !over(); ++t) tick();  // a file's count may be far past the end
      return;
  }
}

void Episode::advance() {
  session_->tick();
  if (environment_) {
    environment_->after_tick(*session_);
    if (--ticks_left_ <= 0 || over()) end_step();
  }
  if (recorder_) recorder_->record(*session_, reward_.total);
}

double Episode::end_step() {
  ticks_left_ = 0;
  const tasks::Reward reward = environment_->end_step(*session_);
  add_to(reward_, reward);
  last_reward_ = reward.total;
  ++env_steps_;
  if (environment_->terminated(*session_)) session_->end_by_task();
  return reward.total;
}

metrics::Recording Episode::recording(std::string termination) const {
  if (!recorder_) throw core::Error(core::ErrorCode::internal, "an episode without a recording has no metrics");
  metrics::Recording recording = recorder_->finish(*session_, std::move(termination));
  if (session_->model().task) {
    recording.episode_reward = reward_.total;
    recording.reward_terms = reward_.terms;
  }
  return recording;
}

}  // namespace hrisim::episode
