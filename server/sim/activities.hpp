#pragma once
// People living by an activity model (scenario::ActivityModel) or a daily schedule
// (scenario::DailySchedule) once the choreography is over: each time one has nothing left to do, what
// comes next is drawn from their own seeded stream.
#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// A walk whose places are all held by others is a pause this long instead, s.
inline constexpr double kPlacesTakenWait = 1.0;

/// Whether anyone in the scenario lives by an activity model: its episode then runs to its time
/// limit (or its task's end) rather than ending with the choreography.
bool anyone_lives_on(const scenario::Model& model);

/// The posture a person's motion leaves them in (standing without one): seated or lying people hold it
/// until they stand up, and others walk round them.
scenario::Posture posture_of(const AgentState& self);

/// The scenario's clock as this session keeps it (its start drawn when the scenario gives a range);
/// the scenario must have a clock.
scenario::Clock session_clock(const scenario::Model& model, const State& state);

/// The activity model a person lives by now: their own, or their daily schedule's for the room they
/// are in; null for anyone else.
const scenario::ActivityModel* activity_model_of(const scenario::Model& model, const State& state, int agent);

/// Once the choreography is over, a person with nothing left to do starts what comes next:
/// - living by an activity model: the model's start first, then one drawn from the row of the
///   activity just done (their type of person's chain); emits "activity_started";
/// - living by a daily schedule: when a stay is over (its drawn length or its hour), a pause or walk
///   under way ends and the next room is drawn from the hour's presence row ("stay_started"); the
///   person stands up if seated or lying, walks to a free spot of the room, and lives there by the
///   room's activity model.
/// Does nothing for anyone else.
void start_next_activity(const scenario::Model& model, State& state, int agent);

}  // namespace hrisim::sim
