#pragma once
// People living by an activity model (scenario::ActivityModel) once the choreography is over: each
// time one has nothing left to do, the next activity is drawn from their own seeded stream.
#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// A walk whose places are all held by others is a pause this long instead, s.
inline constexpr double kPlacesTakenWait = 1.0;

/// Whether anyone in the scenario lives by an activity model: its episode then runs to its time
/// limit (or its task's end) rather than ending with the choreography.
bool anyone_lives_on(const scenario::Model& model);

/// A person living by an activity model with an empty program, the choreography over, starts their
/// next activity: the model's start first, then one drawn from the row of the activity just done
/// (their type of person's chain). Emits "activity_started". Does nothing for anyone else.
void start_next_activity(const scenario::Model& model, State& state, int agent);

}  // namespace hrisim::sim
