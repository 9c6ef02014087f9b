#pragma once
// The search controller (seed 000's apartment search with ARTOS): the robot looks for a named person
// room by room — driving to each room's lookout, turning once around there — until its people
// detector sees the person's face. Rooms come in order of the person's presence probability at the
// current hour (strategy presence) or nearest first (strategy sweep); once all have been looked into,
// it starts over, as the person may have moved.
#include <optional>

#include "robots/differential_drive.hpp"
#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// Turning rate while looking around at a lookout: slow enough for a 10 Hz detector with a 1 rad field
/// of view to see every direction several times (hrisim's value), rad/s.
inline constexpr double kSearchScanRate = 0.5;
/// A lookout is reached this close, m...
inline constexpr double kLookoutRadius = 0.3;
/// ...or the robot looks around from where it is once it has not come kSearchProgress closer to it for
/// kSearchPatience (people in the doorway, a lookout it cannot reach), m and s.
inline constexpr double kSearchProgress = 0.1;
inline constexpr double kSearchPatience = 10.0;

/// The search robot's command this tick: turning at a lookout, standing once the person is found, or
/// nothing (drive along the path to the next lookout, which it sets out to here).
std::optional<robots::Twist> search_command(const scenario::Model& model, State& state, RobotRuntime& runtime);

/// After sensing: a search robot whose detector sees the person's face has found them ("person_found");
/// the episode ends (termination "goal").
void notice_people_found(const scenario::Model& model, State& state);

/// Whether some search robot is still looking (the episode goes on).
bool anyone_searching(const State& state);

}  // namespace hrisim::sim
