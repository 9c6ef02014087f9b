#pragma once
// The Bullet world of a session: people's capsules, robots' links and discs as kinematic bodies that
// follow them, closed doors as slabs, movable objects as dynamic bodies; grasps are made when both of
// a closed gripper's fingers touch an object and released when it opens.
#include <array>
#include <memory>
#include <vector>

#include "humans/body.hpp"
#include "physics/physics_world.hpp"
#include "scenario/model.hpp"
#include "sim/human_bodies.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// A person's body takes part in the physics world within this distance of a robot, m (farther, it
/// cannot touch one: a robot's reach plus a person's).
inline constexpr double kHumanContactRange = 3.0;

/// The world and which body stands for what (fixed once built).
struct PhysicsBodies {
  std::unique_ptr<physics::PhysicsWorld> world;  ///< none without a robot with a model and without objects
  std::vector<std::array<int, humans::kBodyPartCount>> humans;  ///< per agent: a human's capsules (others: -1)
  std::vector<int> doors;
  std::vector<int> disc_robots;               ///< per agent: the body of a robot without a model, else -1
  std::vector<int> objects;
  std::vector<std::vector<int>> robot_links;  ///< per robot with a model: each link's body, -1 without a shape
};

/// The world of the model as the state is now (tick 0); the objects' poses go to the state.
PhysicsBodies build_physics(const scenario::Model& model, State& state, const HumanBodies& bodies);

/// The tick's physics phase: bodies follow their owners, the world steps, grasps change, and the
/// objects' poses go to the state.
void step_physics(const scenario::Model& model, State& state, PhysicsBodies& physics, const HumanBodies& bodies);

}  // namespace hrisim::sim
