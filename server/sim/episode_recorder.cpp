#include "sim/episode_recorder.hpp"

#include <algorithm>

namespace hrisim::sim {

EpisodeRecorder::EpisodeRecorder(const Session& session) {
  const scenario::Model& model = session.model();
  for (std::size_t a = 0; a < model.agents.size() && robot_ < 0; ++a) {
    if (model.agents[a].kind == scenario::AgentKind::robot) robot_ = static_cast<int>(a);
  }
  recording_.dt = model.dt;
  recording_.has_robot = robot_ >= 0;
  if (robot_ >= 0) {
    const scenario::RobotController& controller = model.agents[robot_].controller;
    if (controller.goal && controller.kind != scenario::RobotController::Kind::idle) {
      recording_.goal = controller.goal->position();
      recording_.goal_radius = controller.goal_radius;
    }
  }
  recording_.has_choreography = !model.steps.empty();
  record(session);
}

void EpisodeRecorder::record(const Session& session) {
  const State& state = session.state();
  if (!recording_.samples.empty() && recording_.samples.back().tick == state.tick) return;
  metrics::Sample sample;
  sample.tick = state.tick;
  const scenario::Model& model = session.model();
  std::vector<Contact> touching;
  if (robot_ >= 0) {
    const AgentState& robot = state.agents[robot_];
    sample.robot = {robot_, robot.position, robot.velocity, robot.heading, model.agents[robot_].radius, false};
    if (const RobotRuntime* runtime = session.robot_runtime(session.agent_id(model.agents[robot_].id))) touching = runtime->contacts;
  }
  for (std::size_t a = 0; a < model.agents.size(); ++a) {
    if (model.agents[a].kind != scenario::AgentKind::human || !state.agents[a].active) continue;
    const AgentState& human = state.agents[a];
    const bool touches = std::any_of(touching.begin(), touching.end(), [&](const Contact& c) { return c.agent == static_cast<int>(a); });
    sample.humans.push_back({static_cast<int>(a), human.position, human.velocity, human.heading, model.agents[a].radius, touches});
  }
  recording_.samples.push_back(std::move(sample));
}

metrics::Recording EpisodeRecorder::finish(const Session& session, std::string termination) const {
  metrics::Recording recording = recording_;
  const State& state = session.state();
  for (const Event& event : state.events) {
    metrics::RecordedEvent recorded{event.tick, event.kind, event.subject, std::nullopt};
    if (event.data.contains("request") && event.data["request"].is_number_integer()) recorded.request = event.data["request"].get<std::int64_t>();
    recording.events.push_back(std::move(recorded));
  }
  recording.choreography_completed = state.step >= static_cast<int>(session.model().steps.size());
  recording.termination = termination.empty() ? state.termination : std::move(termination);
  return recording;
}

}  // namespace hrisim::sim
