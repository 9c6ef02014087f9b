#include "sim/queues.hpp"

#include <algorithm>
#include <cmath>

#include "sim/events.hpp"
#include "sim/walking.hpp"

namespace hrisim::sim {
namespace {

/// A service time: Gamma(shape 2, scale mean / 2), the sum of two exponential draws.
double service_time(core::Random& random, double mean) {
  return -0.5 * mean * (std::log1p(-random.uniform()) + std::log1p(-random.uniform()));
}

}  // namespace

void tend_queueing(const scenario::Model& model, State& state, int agent) {
  AgentState& self = state.agents[agent];
  const scenario::Queue& queue = model.queues[self.queueing.queue.value];
  std::vector<int>& line = state.queues[self.queueing.queue.value].line;
  if (self.queueing.place < 0) {
    const Pose2 end = queue.place(static_cast<int>(line.size()));
    if ((self.position - end.position()).norm() <= scenario::kQueueJoinDistance) {
      line.push_back(agent);
      emit(model, state, model.agents[agent].id, events::QueueJoined{queue.name, static_cast<std::int64_t>(line.size()) - 1});
    }
  }
  if (const auto found = std::find(line.begin(), line.end(), agent); found != line.end()) self.queueing.place = static_cast<int>(found - line.begin());
  const Pose2 target = queue.place(self.queueing.place >= 0 ? self.queueing.place : static_cast<int>(line.size()));
  const bool heading_there = self.navigation.under_way && (self.navigation.goal - target.position()).norm() < 1e-6;
  if (!heading_there && (self.position - target.position()).norm() > scenario::kDefaultGoalRadius) {
    go_to(model, state, agent, target, scenario::kDefaultGoalRadius, true);
  }
}

void serve_queues(const scenario::Model& model, State& state) {
  for (std::size_t q = 0; q < state.queues.size(); ++q) {
    QueueState& line = state.queues[q];
    if (line.line.empty()) continue;
    const int head = line.line.front();
    AgentState& person = state.agents[head];
    const scenario::Queue& queue = model.queues[q];
    if (line.served_until_tick < 0) {
      if ((person.position - queue.head.position()).norm() > scenario::kQueueHeadTolerance) continue;
      line.served_until_tick = state.tick + ticks(model, service_time(line.random, queue.service_time));
    }
    if (state.tick < line.served_until_tick) continue;
    line.line.erase(line.line.begin());
    line.served_until_tick = -1;
    person.queueing.served = true;
    person.queueing.queue = {};
    person.queueing.place = -1;
    emit(model, state, model.agents[head].id, events::Served{queue.name});
  }
}

void leave_queue(State& state, int agent) {
  AgentState& self = state.agents[agent];
  if (!self.queueing.queue.valid()) return;
  QueueState& queue = state.queues[self.queueing.queue.value];
  if (!queue.line.empty() && queue.line.front() == agent) queue.served_until_tick = -1;
  std::erase(queue.line, agent);
  self.queueing.queue = {};
  self.queueing.place = -1;
}

}  // namespace hrisim::sim
