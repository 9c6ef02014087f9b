#pragma once
// The Bullet world of a session: people's capsules, robots' links and discs as kinematic bodies that
// follow them, closed doors as slabs, movable objects as dynamic bodies; grasps are made when both of
// a closed gripper's fingers touch an object within their friction cones, and the object stays
// dynamic, held by a joint, until its load exceeds the grip (it slips) or the gripper opens.
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

/// A robot's links may overlap something solid by this much before it stops them, m: none. Resting
/// just clear of what stopped it, the next tick's checks need no penetration-depth search.
inline constexpr double kPenetrationSlop = 0.0;
/// A robot's motion in a tick is checked at points no link is farther than this apart, m: a link as
/// thick cannot pass through a wall between two checks.
inline constexpr double kSweepStep = 0.02;
/// Where a robot stops is found to within this much of its links' travel, m (it ends this close to
/// what stopped it, well inside physics::kContactDistance, so the contact is still reported).
inline constexpr double kStopResolution = 1e-4;

/// Where closing fingers first touch an object is found to within this much of the gripper joint's
/// travel (rad or m).
inline constexpr double kGripResolution = 1e-3;
/// Two finger contacts closer than this hold nothing between them, m.
inline constexpr double kMinGraspWidth = 0.005;
/// Radius of a finger pad's contact patch, m (hrisim's own): its torsional friction, soft-finger
/// style, resists the held object turning about the grasp line up to the payload's weight × this.
inline constexpr double kFingerPadRadius = 0.01;

/// For this long after a grasp its load is not checked, s (hrisim's own): the fingers settle on the
/// object, and the impact of catching it (it may be moving, pushed by the first finger) is not a load
/// the grip must carry.
inline constexpr double kGripSettleTime = 0.1;

/// The world and which body stands for what (fixed once built).
struct PhysicsBodies {
  std::unique_ptr<physics::PhysicsWorld> world;  ///< none without a robot with a model and without objects
  std::vector<std::array<int, humans::kBodyPartCount>> humans;  ///< per agent: a human's capsules (others: -1)
  std::vector<int> doors;
  std::vector<int> disc_robots;               ///< per agent: the body of a robot without a model, else -1
  std::vector<int> objects;
  std::vector<bool> carried;  ///< per object: a person carried it at the last step (its body left out)
  std::vector<std::vector<int>> robot_links;  ///< per robot with a model: each link's body, -1 without a shape
  /// The tick of the state the world was built from, while nothing changed it since (a copy of the
  /// state then carries all of it); -1 once something did between ticks.
  std::int64_t built_at_tick = -1;
};

/// A physics world is built again from the state every this many simulated seconds, at the end of the
/// tick, on every path alike (runs, sessions, replays): a copy of the session taken then (a checkpoint)
/// goes on bit for bit as the session does, so a seek back re-simulates at most this stretch (more when
/// an env step of a task does not end there). Bullet's contact caches, solver warm start and the order
/// of its broadphase pairs, which a world built from the state would not have, start afresh then on
/// every path (velocities, grasps and carried objects are in the state). A copy at any other tick went
/// on differently after hundreds of ticks (the elevator: 695 ticks after a copy at tick 480).
/// hrisim's own; the checkpoint interval (episode::kCheckpointInterval).
inline constexpr double kPhysicsRebuildInterval = 10.0;

/// The world of the model as the state is now (tick 0); the objects' poses go to the state.
PhysicsBodies build_physics(const scenario::Model& model, State& state, const HumanBodies& bodies);


/// The world of a state copied between ticks (of a world that held no history then, or was just built
/// again): as build_physics, with the objects as the state has them (poses, velocities; carried ones
/// out of the world, held ones attached to their hands again) and robots that left the scene out of it
/// as the last tick left them. People and doors are placed again by the next tick before anything
/// meets them.
PhysicsBodies build_physics_again(const scenario::Model& model, const State& state, const HumanBodies& bodies);

/// The tick's last phase: the world built again from the state when one is due (kPhysicsRebuildInterval).
void rebuild_physics_when_due(const scenario::Model& model, const State& state, PhysicsBodies& physics, const HumanBodies& bodies);

/// People's bodies, the doors and robots without a model (they walk with the crowd) as the state has
/// them now, before robots with a model move among them.
void place_people_and_doors(const scenario::Model& model, const State& state, PhysicsBodies& physics, const HumanBodies& bodies);

/// The share (0…1) of the motion from `from` to where robot `robot` (index into State::robots) now is
/// that it can make before a link would overlap something solid — walls, furniture, closed doors,
/// people, other robots — by more than kPenetrationSlop (or, when it already overlaps, more than it does).
double free_share(PhysicsBodies& physics, std::size_t robot, const robots::Robot& moved, const robots::Configuration& from);

/// The tick's physics phase: robots' links follow them, objects people put down or let go of rejoin
/// the world, the world steps, grasps change, and the objects' poses go to the state — a carried
/// object's from the hand that carries it.
void step_physics(const scenario::Model& model, State& state, PhysicsBodies& physics, const HumanBodies& bodies);

}  // namespace hrisim::sim
