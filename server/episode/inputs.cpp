#include "episode/inputs.hpp"

#include "robots/robot.hpp"
#include "sim/session.hpp"

namespace hrisim::episode {
namespace {

struct Give {
  sim::Session& session;
  void operator()(const inputs::HumanCommand& given) const { session.command_human(given.action, given.text); }
  void operator()(const inputs::RobotTwist& given) const { session.command_robot_twist(session.agent_at(given.robot), given.twist); }
  void operator()(const inputs::RobotJoints& given) const {
    session.command_robot_joints(session.agent_at(given.robot), given.group, given.targets, given.velocities);
  }
  void operator()(const inputs::RobotGripper& given) const { session.command_robot_gripper(session.agent_at(given.robot), given.close); }
  void operator()(const inputs::RobotRequest& given) const { session.request(session.agent_at(given.robot), given.routine); }
  void operator()(const inputs::PlaceAgent& given) const { session.place_agent(session.agent_at(given.agent), given.pose); }
  void operator()(const inputs::PlaceObject& given) const { session.place_object(given.object, robots::to_isometry(given.pose)); }
};

}  // namespace

void give_input(sim::Session& session, const Input& input) { std::visit(Give{session}, input); }

}  // namespace hrisim::episode
