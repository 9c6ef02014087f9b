#include "runs/episode.hpp"

#include <cmath>
#include <map>

#include "core/error.hpp"
#include "core/memory_budget.hpp"
#include "metrics/episode_metrics.hpp"
#include "episode/episode.hpp"
#include "runs/event_json.hpp"

namespace hrisim::runs {
namespace {

using nlohmann::json;

json steps_json(const sim::Session& session) {
  const scenario::Model& model = session.model();
  const auto at = [&](std::int64_t tick) { return tick < 0 ? json() : json(static_cast<double>(tick) * model.dt); };
  json steps = json::array();
  for (std::size_t s = 0; s < model.steps.size(); ++s) {
    const sim::StepRecord& step = session.state().steps[s];
    steps.push_back({{"name", model.steps[s].name},
                     {"started", at(step.started_tick)},
                     {"finished", at(step.finished_tick)},
                     {"duration", step.finished_tick < 0 ? json() : at(step.finished_tick - step.started_tick)}});
  }
  return steps;
}

/// An episode whose recording stopped short ends in error: its metrics would describe part of it.
[[noreturn]] void stop_short(std::int64_t tick, const std::string& why) {
  throw core::Error(core::ErrorCode::unavailable, "the episode was stopped at tick " + std::to_string(tick) + ": " + why +
                                                      " (--max-recording-mb); run fewer episodes at once or raise the limit");
}

void check_recording(const sim::EpisodeRecorder& recorder) {
  if (!recorder.stopped().empty()) stop_short(recorder.recorded_until(), recorder.stopped());
}

}  // namespace

std::int64_t trajectory_stride(double dt) { return std::max<std::int64_t>(1, std::llround(1.0 / (kTrajectoryRate * dt))); }

EpisodeResult run_episode(const std::shared_ptr<const scenario::Model>& shared, std::uint64_t seed, const EpisodeOptions& options) {
  const scenario::Model& model = *shared;
  episode::Episode episode(shared, seed, {options.max_time, options.requests, true, {std::nullopt, options.recording_memory}});
  const sim::Session& session = episode.session();

  EpisodeResult result;
  storage::EpisodeRecord& record = result.record;
  core::MemoryBudget::Lease trajectory_memory(options.recording_memory);
  const std::int64_t sample_every = trajectory_stride(model.dt);
  const auto sample_trajectory = [&] {
    const sim::State& state = session.state();
    if (state.tick % sample_every != 0) return;
    for (const sim::AgentId id : session.agent_ids()) {
      const int index = session.index_of(id);
      const sim::AgentState& agent = state.agents[index];
      if (!trajectory_memory.grow(sizeof(storage::TrajectorySample) + model.agents[index].id.size())) {
        stop_short(state.tick, sim::recording_memory_spent(*trajectory_memory.budget()));
      }
      record.trajectory.push_back({model.agents[index].id, state.tick, agent.position.x(), agent.position.y(), agent.heading});
    }
  };
  sample_trajectory();
  if (options.observe) options.observe(session);
  if (!episode.run(options.cancel, [&](const episode::Episode&) {
        check_recording(*episode.recorder());
        sample_trajectory();
        if (options.observe) options.observe(session);
      })) {
    result.cancelled = true;
    return result;
  }

  const sim::State& state = session.state();
  const metrics::Recording recording = episode.recording();
  for (const metrics::MetricValue& metric : metrics::compute_episode_metrics(recording)) {
    record.metrics.push_back({metric.key, metric.value,
                              metric.value ? std::nullopt : std::optional<std::string>(metric.null_reason)});
  }
  if (options.baseline_without_robot) {
    // The same seed once more with the robots taken out at the start: how much further did the
    // people walk because of the robot?
    episode::Episode baseline(shared, seed, {options.max_time, {}, true, {std::nullopt, options.recording_memory}});
    for (const sim::AgentId id : baseline.session().agent_ids()) {
      if (model.agents[baseline.session().index_of(id)].kind == scenario::AgentKind::robot) baseline.session().remove_agent(id);
    }
    if (!baseline.run(options.cancel, [](const episode::Episode& ticked) { check_recording(*ticked.recorder()); })) {
      result.cancelled = true;
      return result;
    }
    const auto deviation = metrics::human_path_deviation(recording, baseline.recording());
    for (storage::MetricValue& metric : record.metrics) {
      if (metric.key != "human_path_deviation") continue;
      metric.value = deviation;
      metric.null_reason = deviation ? std::nullopt : std::optional<std::string>("no person was in both runs");
    }
  }
  // Series are kept at the trajectory's rate: enough for plots, a sixth of the steps at 60 Hz.
  for (metrics::Series& series : metrics::compute_series(recording)) {
    storage::SeriesRecord kept{series.name, recording.samples.front().tick, sample_every, {}};
    for (std::size_t i = 0; i < series.values.size(); i += static_cast<std::size_t>(sample_every)) kept.values.push_back(series.values[i]);
    record.series.push_back(std::move(kept));
  }
  std::map<std::string, int> counts;
  for (const sim::Event& event : state.events) {
    ++counts[std::string(event.kind())];
    record.events.push_back({event.tick, event.time, std::string(event.kind()), event.subject, event_data_json(event.data)});
  }
  record.seed = seed;
  record.status = "finished";
  record.termination_reason = sim::to_string(state.termination);
  record.ticks = state.tick;
  record.sim_time = session.time();
  record.state_hash = session.state_hash_hex();

  json agents = json::array();
  for (std::size_t a = 0; a < model.agents.size(); ++a) {
    const sim::AgentState& agent = state.agents[a];
    agents.push_back({{"id", model.agents[a].id},
                      {"x", agent.position.x()},
                      {"y", agent.position.y()},
                      {"theta", agent.heading},
                      {"busy", !agent.program.empty()}});
  }
  const bool in_step = state.current_step < static_cast<int>(model.steps.size());
  json metric_values = json::object();
  for (const storage::MetricValue& metric : record.metrics) metric_values[metric.key] = metric.value ? json(*metric.value) : json();
  const json current_step = in_step ? json{{"index", state.current_step}, {"name", model.steps[state.current_step].name}} : json();
  result.summary = {{"scenario", model.name},
                    {"seed", seed},
                    {"dt", model.dt},
                    {"ticks", state.tick},
                    {"sim_time", session.time()},
                    {"completed", state.termination == sim::Termination::scenario_end},
                    {"termination", sim::to_string(state.termination)},
                    {"current_step", current_step},
                    {"step", current_step},  // the former name, kept for one version
                    {"steps", steps_json(session)},
                    {"events", counts},
                    {"agents", agents},
                    {"metrics", metric_values},
                    {"state_hash", record.state_hash}};
  return result;
}

}  // namespace hrisim::runs
