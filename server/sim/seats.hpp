#pragma once
// Sitting on a seat (scenario::Seat, an obstacle's anchor): the person plans to the free spot in front
// of it, steps back onto the seat's spot (the chair is solid to the planner and to avoidance, so the
// last step is a controlled one), sits down and stays seated; before walking anywhere else they stand
// up and step back off. One person per seat.
#include <optional>

#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// A person stepping onto or off a seat's spot is there within this distance, m.
inline constexpr double kSeatStepTolerance = 0.01;

/// Starts sitting on `seat`: false while someone else has it (try again next tick). A seat whose front
/// no longer admits this person emits "seat_unreachable" and leaves the person where they are.
bool start_sitting(const scenario::Model& model, State& state, int agent, int seat);
/// Whether a sit_on of `seat` is over: seated there, or given up (unreachable).
bool sitting_done(const State& state, int agent, int seat);

/// Whether the action walks the person away from the seat they are on (so they get up first).
bool leaves_seat(const scenario::Action& action, const AgentState& self);
/// Has the person get up from their seat, or let go of one they were walking to: true once clear of
/// it, false while standing up or stepping off (ask again next tick).
bool clear_of_seat(State& state, int agent);

/// The tick's seat phases for one person: arriving in front of the seat, stepping onto it, sitting
/// down ("sat_down"), standing up and stepping off ("stood_up").
void tend_seat(const scenario::Model& model, State& state, int agent);

/// The velocity of a person stepping onto or off a seat's spot this tick (avoidance does not move
/// them), or none.
std::optional<Vec2> seat_step_velocity(const scenario::Model& model, const State& state, int agent);
/// Whether a person is held where they are by a seat: sitting down, seated or standing up.
bool held_by_seat(const AgentState& self);

}  // namespace hrisim::sim
