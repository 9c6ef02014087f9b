#pragma once
// People picking up and putting down movable objects: a pick_up or put_down walks the person to a free
// spot within reach (scenario::reach_spot), turns them to the place, and plays the reach motion; at
// its lowest point the hand takes the object or leaves it. A carried object rides in the right hand:
// the physics world leaves it out and the state puts it where the hand is, every tick.
#include <Eigen/Geometry>

#include "scenario/model.hpp"
#include "sim/human_bodies.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// The reach motion (assets/motions/reach.json) has the hand lowest, at the item, this far in, s.
inline constexpr double kReachGraspTime = 0.8;
/// A carried object's centre is this far beyond the wrist along the forearm, m (in the hand's grip).
inline constexpr double kGripOffset = 0.08;
/// A put-down object is left this far above the surface it rests on, m, so that it starts clear of it
/// and settles.
inline constexpr double kPutDownClearance = 0.002;

/// Starts a pick_up or put_down: false while someone else holds the object (try again next tick).
/// One that cannot be done — the object out of reach, the hands full, nothing carried — emits
/// "pick_up_skipped" or "put_down_skipped" with the reason, and is over at once.
bool start_reaching(const scenario::Model& model, State& state, int agent, const scenario::Action& action);
/// The tick's part of a pick_up or put_down under way: arrived and facing the place, the person plays
/// the reach motion; at kReachGraspTime the object changes hands ("picked_up", "put_down"). A pick_up
/// whose object someone else takes, or that moves out of reach, before the hand gets there starts over
/// (ReachPhase::none: the choreography starts the action again).
void tend_reaching(const scenario::Model& model, State& state, int agent, const scenario::Action& action);
/// Whether a pick_up or put_down is over.
bool reaching_done(const State& state, int agent);

/// Where the object a person carries is: in their right hand, upright, turned with them.
Eigen::Isometry3d carried_pose(const scenario::Model& model, const State& state, const HumanBodies& bodies, int agent);

}  // namespace hrisim::sim
