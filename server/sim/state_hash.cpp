#include "sim/state.hpp"

#include <cstdio>

#include "core/state_hash.hpp"

namespace hrisim::sim {

std::uint64_t state_hash(const State& state) {
  core::StateHasher hash;
  hash.add(state.tick).add(state.step).add(state.finished);
  for (const AgentState& agent : state.agents) {
    hash.add(agent.active);
    hash.add(agent.position.x()).add(agent.position.y()).add(agent.velocity.x()).add(agent.velocity.y());
    hash.add(agent.heading).add(agent.preferred_speed).add(static_cast<std::int64_t>(agent.program.size()));
    hash.add(agent.navigating).add(static_cast<std::int64_t>(agent.path_index)).add(static_cast<std::int64_t>(agent.path.size()));
    hash.add(agent.leg_start.x()).add(agent.leg_start.y());
    hash.add(agent.reserved_location).add(agent.reserved_space).add(agent.reserved_slot);
    hash.add(agent.follow_leader).add(agent.harass_robot).add(agent.watched_robot);
  }
  for (const auto& [topic, message] : state.topics) hash.add(std::string_view(topic)).add(std::string_view(message));
  for (const auto& members : state.groups) {
    for (int member : members) hash.add(member);
    hash.add(-1);
  }
  for (const DoorState& door : state.doors) hash.add(static_cast<int>(door.phase)).add(door.opening);
  for (const ElevatorState& cabin : state.elevators) {
    hash.add(static_cast<int>(cabin.phase)).add(cabin.floor).add(static_cast<std::int64_t>(cabin.queue.size()));
  }
  hash.add(static_cast<std::int64_t>(state.requests.size())).add(static_cast<std::int64_t>(state.events.size()));
  hash.add(static_cast<std::int64_t>(state.commanded.size()));
  for (std::uint64_t word : state.random.state()) hash.add(word);
  for (const AgentState& agent : state.agents) {
    hash.add(agent.rooted);
    hash.add(agent.gait_distance);
    hash.add(agent.turn_rate);
    hash.add(agent.motion ? agent.motion->name() : std::string());
    hash.add(agent.motion_tick);
    hash.add(agent.motion_released_tick);
  }
  for (const RobotRuntime& runtime : state.robots) runtime.hash(hash);
  for (const Eigen::Isometry3d& pose : state.object_poses) {
    for (int k = 0; k < 16; ++k) hash.add(pose.data()[k]);
  }
  return hash.value();
}

std::string hash_hex(std::uint64_t hash) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

}  // namespace hrisim::sim
