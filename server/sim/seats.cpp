#include "sim/seats.hpp"

#include <algorithm>

#include "scenario/reaching.hpp"
#include "sim/choreography.hpp"
#include "sim/events.hpp"
#include "sim/walking.hpp"

namespace hrisim::sim {
namespace {

using Kind = scenario::Action::Kind;

void play(State& state, AgentState& self, const char* motion) {
  self.animation.motion = humans::builtin_motion(motion);
  self.animation.motion_tick = state.tick;
  self.animation.motion_released_tick = -1;
}

bool motion_over(const scenario::Model& model, const State& state, const AgentState& self, const char* motion) {
  return static_cast<double>(state.tick - self.animation.motion_tick) * model.dt >= humans::builtin_motion(motion)->duration();
}

void leave(AgentState& self) {
  self.seating.seat = {};
  self.seating.phase = SeatPhase::none;
}

}  // namespace

bool start_sitting(const scenario::Model& model, State& state, int agent, int seat) {
  AgentState& self = state.agents[agent];
  if (self.seating.seat.value == seat) return true;  // already there or on the way
  const bool taken = std::any_of(state.agents.begin(), state.agents.end(), [&](const AgentState& other) { return &other != &self && other.active && other.seating.seat.value == seat; });
  if (taken) return false;
  const scenario::Seat& place = model.seats[seat];
  const std::optional<Vec2> front = scenario::seat_approach(model, place, model.agents[agent].radius);
  if (!front) {
    emit(model, state, model.agents[agent].id, events::SeatUnreachable{place.name});
    return true;
  }
  release_reservations(state, agent);
  self.seating.seat = SeatIndex(seat);
  self.seating.phase = SeatPhase::approaching;
  self.seating.front = *front;
  go_to(model, state, agent, {front->x(), front->y(), place.pose.theta}, scenario::kReachSpotRadius, true);
  return true;
}

bool sitting_done(const State& state, int agent, int seat) {
  const AgentState& self = state.agents[agent];
  return self.seating.seat.value != seat || self.seating.phase == SeatPhase::seated;
}

bool leaves_seat(const scenario::Action& action, const AgentState& self) {
  if (!self.seating.seat.valid()) return false;
  switch (action.kind) {
    case Kind::go_to_location:
    case Kind::go_to_social_space:
    case Kind::go_to_pose:
    case Kind::harass:
    case Kind::pick_up:
    case Kind::put_down:
      return true;
    case Kind::sit_on:
      return action.target != self.seating.seat.value;
    case Kind::play_motion:
      return action.motion == "stand_up";
    default:
      return false;
  }
}

bool clear_of_seat(State& state, int agent) {
  AgentState& self = state.agents[agent];
  switch (self.seating.phase) {
    case SeatPhase::none:
      return true;
    case SeatPhase::approaching:
      self.navigation.under_way = false;
      self.navigation.path.clear();
      leave(self);
      return true;
    case SeatPhase::stepping_in:
      self.seating.phase = SeatPhase::stepping_out;
      return false;
    case SeatPhase::seated:
      self.seating.phase = SeatPhase::standing_up;
      play(state, self, "stand_up");
      return false;
    case SeatPhase::sitting:  // sits down first, then gets up
    case SeatPhase::standing_up:
    case SeatPhase::stepping_out:
      return false;
  }
  return false;
}

void tend_seat(const scenario::Model& model, State& state, int agent) {
  AgentState& self = state.agents[agent];
  if (!self.seating.seat.valid()) return;
  const scenario::Seat& seat = model.seats[self.seating.seat.value];
  switch (self.seating.phase) {
    case SeatPhase::none:
    case SeatPhase::seated:
      return;
    case SeatPhase::approaching:
      // Arrived in front of the seat and turned its way: the last step is backwards onto it.
      if (!self.navigation.under_way && !self.attitude.target_heading) self.seating.phase = SeatPhase::stepping_in;
      return;
    case SeatPhase::stepping_in:
      if ((scenario::seat_spot(seat) - self.position).norm() > kSeatStepTolerance) return;
      self.position = scenario::seat_spot(seat);
      self.velocity = Vec2::Zero();
      self.heading = seat.pose.theta;
      self.navigation.hold = self.position;
      self.seating.phase = SeatPhase::sitting;
      play(state, self, "sit_down");
      return;
    case SeatPhase::sitting:
      if (!motion_over(model, state, self, "sit_down")) return;
      self.seating.phase = SeatPhase::seated;
      emit(model, state, model.agents[agent].id, events::SatDown{seat.name});
      return;
    case SeatPhase::standing_up:
      if (motion_over(model, state, self, "stand_up")) self.seating.phase = SeatPhase::stepping_out;
      return;
    case SeatPhase::stepping_out:
      if ((self.seating.front - self.position).norm() > kSeatStepTolerance) return;
      self.position = self.seating.front;
      self.velocity = Vec2::Zero();
      self.navigation.hold = self.position;
      leave(self);
      emit(model, state, model.agents[agent].id, events::StoodUp{seat.name});
      return;
  }
}

std::optional<Vec2> seat_step_velocity(const scenario::Model& model, const State& state, int agent) {
  const AgentState& self = state.agents[agent];
  if (self.seating.phase != SeatPhase::stepping_in && self.seating.phase != SeatPhase::stepping_out) return std::nullopt;
  const Vec2 to = (self.seating.phase == SeatPhase::stepping_in ? scenario::seat_spot(model.seats[self.seating.seat.value]) : self.seating.front) - self.position;
  const double distance = to.norm();
  if (distance <= 0.0) return Vec2::Zero();
  return to / distance * std::min(scenario::kSeatStepSpeed, distance / model.dt);
}

bool held_by_seat(const AgentState& self) {
  return self.seating.phase == SeatPhase::sitting || self.seating.phase == SeatPhase::seated || self.seating.phase == SeatPhase::standing_up;
}

}  // namespace hrisim::sim
