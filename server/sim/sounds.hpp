#pragma once
// The sounds of a session, kept only when some robot listens (scenario::Model::heard): people's speech
// (the `say` action and command), their footfalls as they walk, doors shutting, the elevator's chime;
// and what the robots' microphone arrays record of them each tick, with the direction of arrival.
#include <cstddef>
#include <Eigen/Core>

#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// Where a person's voice comes from: an adult's mouth, standing, m above the floor.
inline constexpr double kMouthHeight = 1.55;
/// Where a door's shutting is heard from (its middle), m.
inline constexpr double kDoorSoundHeight = 1.0;
/// Where the elevator's chime sounds: above its door on the floor it arrives at, m.
inline constexpr double kChimeHeight = 2.2;
/// Where a robot's motors sound: its drive, above the floor, m.
inline constexpr double kMotorHeight = 0.1;

/// A person begins saying something (a `say` action): their voice for the action's duration, or its clip.
void start_speaking(const scenario::Model& model, State& state, int agent, const scenario::Action& action);

/// The tick's new sounds, at its start time: footfalls of the people walking, doors that shut and the
/// chime of an elevator arriving (from the tick's events since `first_event`); speakers' voices follow
/// them; sounds that have passed beyond the map are dropped.
void make_sounds(const scenario::Model& model, State& state, std::size_t first_event);

/// After the tick: every listening robot records the tick's samples and, at its rate, the direction of
/// arrival.
void listen(const scenario::Model& model, State& state);

/// Walls between two points: the map's walls (obstacles without a furniture mesh; for a map from an
/// image, its outline's crossings, two per wall) and doors not fully open.
int walls_between(const scenario::Model& model, const State& state, const Eigen::Vector3d& from, const Eigen::Vector3d& to);

}  // namespace hrisim::sim
