#include "sim/episode_recorder.hpp"

#include <algorithm>

#include "metrics/definitions.hpp"

namespace hrisim::sim {

namespace {

/// Memory a sample would take unpacked: more than it takes packed, so a lease that covers it covers
/// what appending the sample adds.
std::size_t sample_bytes(const metrics::Sample& sample) {
  std::size_t bytes = sizeof(metrics::Sample) + sample.humans.capacity() * sizeof(metrics::Body);
  for (const std::vector<int>& group : sample.groups) bytes += sizeof(group) + group.capacity() * sizeof(int);
  for (const std::string& name : sample.touched_obstacles) bytes += sizeof(name) + name.capacity();
  return bytes;
}

/// Whether the choreography gives the robot something to do: an action of a step, or a request it
/// makes (the scenario's or one scheduled for the episode).
bool robot_takes_part(const scenario::Model& model, const State& state, int robot) {
  for (const scenario::Step& step : model.steps) {
    if (std::any_of(step.actions.begin(), step.actions.end(), [robot](const scenario::Action& action) { return action.agent == robot; })) return true;
  }
  return std::any_of(state.scheduled.begin(), state.scheduled.end(), [robot](const ScheduledRequest& request) { return request.robot == robot; });
}

}  // namespace

std::string recording_memory_spent(const core::MemoryBudget& memory) {
  const std::size_t limit = memory.limit();
  const std::string amount = limit % (1 << 20) == 0 ? std::to_string(limit >> 20) + " MiB" : std::to_string(limit >> 10) + " KiB";
  return "the recordings of all sessions and runs hold their maximum of " + amount;
}

EpisodeRecorder::EpisodeRecorder(const Session& session, RecorderLimits limits)
    : max_bodies_(limits.max_bodies), memory_(limits.memory) {
  const scenario::Model& model = session.model();
  for (std::size_t a = 0; a < model.agents.size() && robot_ < 0; ++a) {
    if (model.agents[a].kind == scenario::AgentKind::robot) robot_ = static_cast<int>(a);
  }
  recording_.dt = model.dt;
  recording_.has_robot = robot_ >= 0;
  if (robot_ >= 0) {
    const scenario::RobotController& controller = model.agents[robot_].controller;
    recording_.searching = controller.kind == scenario::RobotController::Kind::search;
    if (controller.goal && controller.kind != scenario::RobotController::Kind::idle) {
      recording_.goal = controller.goal->position();
      recording_.goal_radius = controller.goal_radius;
      const Vec2 start = session.state().agents[robot_].position;
      if (const auto path = model.planner.plan(start, *recording_.goal, model.agents[robot_].radius)) {
        double length = 0.0;
        Vec2 from = start;
        for (const Vec2& waypoint : *path) {
          length += (waypoint - from).norm();
          from = waypoint;
        }
        recording_.shortest_path_length = length;
      }
    }
  }
  recording_.has_choreography = !model.steps.empty();
  recording_.robot_in_choreography = robot_ >= 0 && robot_takes_part(model, session.state(), robot_);
  if (model.task) recording_.task_goal_condition = scenario::has_goal_condition(model.task->kind);
  record(session);
}

void EpisodeRecorder::record(const Session& session, double reward) {
  const State& state = session.state();
  if (!samples_.empty() && samples_.back().tick == state.tick) return;
  if (!stopped_.empty()) return;
  if (max_bodies_ && bodies_ >= *max_bodies_) {
    stopped_ = "the session's recording holds its maximum of " + std::to_string(*max_bodies_) + " bodies";
    return;
  }
  metrics::Sample sample;
  sample.tick = state.tick;
  sample.reward = reward;
  const scenario::Model& model = session.model();
  std::vector<Contact> touching;
  if (robot_ >= 0) {
    const AgentState& robot = state.agents[robot_];
    const double radius = model.agents[robot_].radius;
    sample.robot = {robot_, robot.position, robot.velocity, robot.heading, radius, false};
    // The distance field runs between cell centres: half a cell is the obstacle's own.
    sample.obstacle_distance = std::max(model.field.distance(model.grid, robot.position) - model.grid.resolution() / 2 - radius, 0.0);
    const RobotRuntime* runtime = robot.active ? session.robot_runtime(session.agent_at(robot_)) : nullptr;
    if (runtime) {
      touching = runtime->contacts;
      for (const Contact& contact : touching) {
        if (contact.agent >= 0) continue;
        sample.touched_obstacles.push_back(contact.object >= 0 ? model.objects[contact.object].name : contact.part.empty() ? "map" : contact.part);
      }
    } else if (sample.obstacle_distance < metrics::kContactDistance) {
      sample.touched_obstacles.push_back("map");  // a disc robot has no physics body: touching is being this close
    }
  }
  for (std::size_t a = 0; a < model.agents.size(); ++a) {
    if (model.agents[a].kind != scenario::AgentKind::human || !state.agents[a].active) continue;
    const AgentState& human = state.agents[a];
    const bool touches = std::any_of(touching.begin(), touching.end(), [&](const Contact& c) { return c.agent == static_cast<int>(a); });
    sample.humans.push_back({static_cast<int>(a), human.position, human.velocity, human.heading, model.agents[a].radius, touches});
  }
  for (const std::vector<int>& members : state.groups) {
    std::vector<int> present;
    for (const int agent : members) {
      const auto found = std::find_if(sample.humans.begin(), sample.humans.end(), [&](const metrics::Body& b) { return b.agent == agent; });
      if (found != sample.humans.end()) present.push_back(static_cast<int>(found - sample.humans.begin()));
    }
    if (present.size() >= 2) sample.groups.push_back(std::move(present));
  }
  // The lease grows a block at a time, ahead of what the packed samples hold.
  const std::size_t needed = samples_.bytes() + sample_bytes(sample);
  if (memory_.bytes() < needed && !memory_.grow(std::max(needed - memory_.bytes(), metrics::PackedSamples::kBlockBytes)) && !samples_.empty()) {
    stopped_ = recording_memory_spent(*memory_.budget());
    return;
  }
  bodies_ += sample.humans.size() + 1;
  samples_.append(sample);
}

void EpisodeRecorder::forget_after(std::int64_t tick) {
  bodies_ = 0;
  samples_.keep_until(tick, [this](const metrics::Sample& sample) { bodies_ += sample.humans.size() + 1; });
  if (memory_.bytes() > samples_.bytes()) memory_.shrink(memory_.bytes() - samples_.bytes());
  if (recorded_until() == tick) stopped_.clear();  // it stopped after the tick: that is another branch now
}

metrics::Recording EpisodeRecorder::finish(const Session& session, std::string termination) const {
  metrics::Recording recording = recording_;
  recording.samples = samples_.unpack();
  const State& state = session.state();
  for (const Event& event : state.events) {
    if (event.tick > recorded_until()) break;  // after what was recorded (events are in tick order)
    using Kind = metrics::RecordedEvent::Kind;
    if (const auto* request = event.as<events::Request>()) {
      recording.events.push_back({event.tick, Kind::request, request->request});
    } else if (const auto* accepted = event.as<events::RequestAccepted>()) {
      recording.events.push_back({event.tick, Kind::request_accepted, accepted->request});
    } else if (const auto* dropped = event.as<events::RequestDropped>()) {
      recording.events.push_back({event.tick, Kind::request_dropped, dropped->request});
    } else if (event.is<events::PersonFound>()) {
      recording.events.push_back({event.tick, Kind::person_found, std::nullopt});
    }
  }
  recording.choreography_completed = state.current_step >= static_cast<int>(session.model().steps.size());
  recording.termination = termination.empty() ? std::string(to_string(state.termination)) : std::move(termination);
  return recording;
}

}  // namespace hrisim::sim
