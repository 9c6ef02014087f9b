#pragma once
// What drives an episode from outside between ticks, as data: commands to people and robots, a robot's
// request, placements. An input names agents and objects by their index in the scenario's model; it is
// given to a session by give_input, kept in the episode's input log, and (at the edges) written as the
// API's own JSON, so that a log can be stored, sent, shown and read back through the same checks.
#include <string>
#include <variant>
#include <vector>

#include "core/math.hpp"
#include "robots/differential_drive.hpp"
#include "scenario/model.hpp"

namespace hrisim::sim {
class Session;
}

namespace hrisim::episode {

namespace inputs {

/// A text command to a person (`text` as given; `action` what it says, parsed and checked).
struct HumanCommand {
  int human = -1;
  scenario::Action action;
  std::string text;
};
struct RobotTwist {
  int robot = -1;
  robots::Twist twist;
};
struct RobotJoints {
  int robot = -1;
  std::string group;
  std::vector<double> targets;
  bool velocities = false;  ///< targets are joint velocities, not positions
};
struct RobotGripper {
  int robot = -1;
  bool close = false;
};
/// The robot asks for a routine (IMHuS's asynchronous request).
struct RobotRequest {
  int robot = -1;
  int routine = -1;
};
/// A person or robot set down upright at a pose on the floor.
struct PlaceAgent {
  int agent = -1;
  core::Pose2 pose;
};
struct PlaceObject {
  int object = -1;
  core::Pose3 pose;
};

}  // namespace inputs

using Input = std::variant<inputs::HumanCommand, inputs::RobotTwist, inputs::RobotJoints, inputs::RobotGripper, inputs::RobotRequest,
                           inputs::PlaceAgent, inputs::PlaceObject>;

/// Gives the input to the session now. Inputs are checked when made (at the edge that reads them);
/// what the session still refuses (an object placed off the floor) throws before changing anything.
void give_input(sim::Session& session, const Input& input);

}  // namespace hrisim::episode
