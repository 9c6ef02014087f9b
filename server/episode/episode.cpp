#include "episode/episode.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "tasks/task_support.hpp"

namespace hrisim::episode {
namespace {

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
    : model_(model), seed_(seed), settings_(settings), session_(std::make_unique<sim::Session>(std::move(model), seed)) {
  const scenario::Model& scenario = session_->model();
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
  if (environment_ && environment_->terminated()) session_->end_by_task();
  if (settings.record) recorder_.emplace(*session_, settings.recording);
}

double Episode::step(const std::optional<std::vector<double>>& action, std::int64_t n) {
  if (action && environment_) tasks::check_action(*action, static_cast<std::size_t>(environment_->action_space().shape.at(0)));
  log_.push_back({Snapshot::Entry::Kind::step, nullptr, action, n});
  double reward = 0.0;
  for (std::int64_t i = 0; i < n && !over(); ++i) {
    if (!environment_) {
      advance();
      continue;
    }
    if (ticks_left_ > 0) reward += end_step();  // a clock's env step under way ends here
    ticks_left_ = environment_->begin_step(*session_, i == 0 ? action : std::nullopt);
    if (ticks_left_ <= 0) {
      reward += end_step();
      continue;
    }
    const std::int64_t before = env_steps_;
    while (env_steps_ == before) advance();
    reward += last_reward_;
  }
  return reward;
}

void Episode::tick() {
  if (over()) return;
  log_ticks(1);
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
  input(*session_);
  log_.push_back({Snapshot::Entry::Kind::input, input, std::nullopt, 0});
}

void Episode::log_ticks(std::int64_t count) {
  if (!log_.empty() && log_.back().kind == Snapshot::Entry::Kind::ticks) {
    log_.back().count += count;
  } else {
    log_.push_back({Snapshot::Entry::Kind::ticks, nullptr, std::nullopt, count});
  }
}

Episode::Snapshot Episode::snapshot() const { return {log_, session_->state().tick, session_->state_hash()}; }

std::unique_ptr<Episode> Episode::restore(const Snapshot& snapshot) const {
  auto restored = std::make_unique<Episode>(model_, seed_, settings_);
  for (const Snapshot::Entry& entry : snapshot.log) restored->replay(entry);
  if (restored->session().state_hash() != snapshot.state_hash) {
    throw core::Error(core::ErrorCode::internal, "restoring the snapshot of tick " + std::to_string(snapshot.tick) +
                                                     " did not reach its state: the simulation was not deterministic here");
  }
  return restored;
}

std::unique_ptr<Episode> Episode::rewind(std::int64_t tick) const {
  auto rewound = std::make_unique<Episode>(model_, seed_, settings_);
  const auto at_tick = [&] { return rewound->session().state().tick >= tick; };
  for (const Snapshot::Entry& entry : log_) {
    if (entry.kind == Snapshot::Entry::Kind::input) {
      rewound->give(entry.input);
      continue;
    }
    std::int64_t done = 0;
    for (; done < entry.count && !at_tick() && !rewound->over(); ++done) {
      // One env step at a time, the action at the first: the same ticks as step(action, count).
      if (entry.kind == Snapshot::Entry::Kind::step) {
        rewound->step(done == 0 ? entry.action : std::nullopt, 1);
      } else {
        rewound->tick();
      }
    }
    if (done < entry.count && at_tick()) break;  // cut short: what follows was given after `tick`
  }
  return rewound;
}

void Episode::replay(const Snapshot::Entry& entry) {
  switch (entry.kind) {
    case Snapshot::Entry::Kind::input:
      give(entry.input);
      return;
    case Snapshot::Entry::Kind::step:
      step(entry.action, entry.count);
      return;
    case Snapshot::Entry::Kind::ticks:
      for (std::int64_t t = 0; t < entry.count; ++t) tick();
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
  if (environment_->terminated()) session_->end_by_task();
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
