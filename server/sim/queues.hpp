#pragma once
// Waiting lines (scenario::Queue, Pedsim's <queue>): a person given join_queue walks to the end of the
// line and joins it within kQueueJoinDistance of their place; they move up as those ahead are served;
// at the head they are served for a time drawn from Gamma(shape 2, mean / 2), then their action is done.
#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// While the person's join_queue runs: joins the line once near its end, and walks to their place in
/// it whenever that place moves (or they were drawn away from it).
void tend_queueing(const scenario::Model& model, State& state, int agent);

/// The tick's service at every head: it begins once the person at the head stands there; when it ends
/// they are served (their join_queue is done) and leave the line.
void serve_queues(const scenario::Model& model, State& state);

/// Takes the person out of the line they are in or walking to (their action ended another way, or
/// they left the scene); the people behind move up.
void leave_queue(State& state, int agent);

}  // namespace hrisim::sim
