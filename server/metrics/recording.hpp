#pragma once
// What an episode leaves behind for its metrics: the robot under test and every human at every step,
// and the events. Filled by the simulation (sim::EpisodeRecorder); metrics only read it.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/math.hpp"

namespace hrisim::metrics {

using core::Vec2;

/// A disc-shaped body at one step.
struct Body {
  int agent = -1;  ///< which agent of the scenario, stable across samples
  Vec2 position = Vec2::Zero();
  Vec2 velocity = Vec2::Zero();
  double heading = 0.0;
  double radius = 0.0;
  bool touching_robot = false;  ///< humans: the physics reports contact with the robot's body
};

struct Sample {
  std::int64_t tick = 0;
  Body robot;
  std::vector<Body> humans;  ///< the humans present at this step
};

struct RecordedEvent {
  std::int64_t tick = 0;
  std::string kind;
  std::string subject;
  std::optional<std::int64_t> request;  ///< request events: the request's id
};

struct Recording {
  double dt = 0.0;
  bool has_robot = false;  ///< false: the robot metrics are null
  std::optional<Vec2> goal;  ///< the robot's navigation goal, when it has one
  double goal_radius = 0.0;
  bool has_choreography = false;
  bool choreography_completed = false;
  std::string termination;  ///< goal, collision, timeout, scenario_end, cancelled, error
  std::vector<Sample> samples;  ///< one per simulation step, the initial state first
  std::vector<RecordedEvent> events;
};

}  // namespace hrisim::metrics
