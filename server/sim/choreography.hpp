#pragma once
// The choreography (IMHuS): steps run in order, each giving its agents actions; an agent works
// through its program one action at a time (compound routines expanded as they start); a step ends
// when all its actions are done. Robot requests wait for the closest idle human within reach, who then
// runs the asked routine.
#include <span>

#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// A human answers a robot request only within this distance of where the robot asked (IMHuS).
inline constexpr double kRequestRadius = 3.0;
/// An unanswered request is tried again this often, in seconds...
inline constexpr double kRequestRetryPeriod = 5.0;
/// ...until it is this old, then dropped (counted as a failure), in seconds.
inline constexpr double kRequestTimeout = 30.0;

/// Gives the agents of choreography step `step` its actions.
void start_step(const scenario::Model& model, State& state, int step);

/// The tick's phase for robot requests: an open request is offered to the closest idle human within
/// kRequestRadius, tried again every kRequestRetryPeriod and dropped after kRequestTimeout.
void update_requests(const scenario::Model& model, State& state);

/// The tick's phase for the choreography: every agent starts or finishes what its program says; a
/// finished step hands over to the next within the same tick. The episode of a scenario without a
/// benchmark task ends with its last step.
void update_choreography(const scenario::Model& model, State& state);

/// Robot `robot` asks for routine `routine` now (IMHuS's asynchronous step).
void make_request(const scenario::Model& model, State& state, int robot, int routine);

/// The action a program entry stands for (a step's, a routine's, or a command's).
const scenario::Action& action_of(const scenario::Model& model, const State& state, const PendingAction& pending);

/// Gives up the location, social space and slot an agent holds.
void release_reservations(State& state, int agent);

/// The agent leaves the scene for good: out of the crowd, its groups and lines, its program dropped;
/// `event` (events::Left, events::AgentRemoved) says so.
void leave_scene(const scenario::Model& model, State& state, int agent, EventData event);

/// Humans whose enters_at has come appear at their start (event "entered").
void let_people_in(const scenario::Model& model, State& state);

/// Puts `actions` before everything in a human's program, in order; what they were doing starts
/// again afterwards (commands and reactions).
void interrupt(State& state, int human, std::span<const scenario::Action> actions);

/// A person touched by a robot steps back this far from it, m (half as far when that spot is taken;
/// not at all when neither is free, in a social space such as a cabin, or standing their ground)...
inline constexpr double kStartleStepBack = 0.5;
/// ...then looks at the robot this long before going on with what they were doing, s.
inline constexpr double kStartleLook = 1.0;
/// Touches within this long of the last one startle nobody again, s.
inline constexpr double kStartleRefractory = 3.0;

/// A robot touched `human`: they stop what they do, step back, look at the robot, then carry on (the
/// reaction goes before their program, as a command would). Emits "startled".
void startle(const scenario::Model& model, State& state, int human, int robot);

}  // namespace hrisim::sim
