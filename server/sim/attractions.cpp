#include "sim/attractions.hpp"

#include <cmath>
#include <limits>

#include "sim/choreography.hpp"
#include "sim/events.hpp"

namespace hrisim::sim {

void draw_people_to_attractions(const scenario::Model& model, State& state) {
  if (model.attractions.empty()) return;
  for (std::size_t a = 0; a < state.agents.size(); ++a) {
    AgentState& self = state.agents[a];
    if (!self.active || model.agents[a].kind != scenario::AgentKind::human || !self.navigation.under_way || self.program.empty()) continue;
    if (self.program.front().routine == kCommandedAction || self.queueing.queue.valid() || self.seating.seat.valid() || self.attitude.follow_leader.valid() || self.reaction.reacting_to.valid()) continue;
    const scenario::Attraction* nearest = nullptr;
    double distance = std::numeric_limits<double>::infinity();
    for (const scenario::Attraction& attraction : model.attractions) {
      const double d = (attraction.centre - self.position).norm();
      if (d < distance) {
        distance = d;
        nearest = &attraction;
      }
    }
    if (distance >= scenario::kAttractionReach) continue;
    const double chance = scenario::kAttractionRate * nearest->strength * (1.0 - distance / scenario::kAttractionReach) * model.dt;
    if (state.attraction_random.uniform() >= chance) continue;
    core::Random& random = state.attraction_random;
    const Vec2 spot = nearest->centre + Vec2(random.uniform(-nearest->width / 2, nearest->width / 2), random.uniform(-nearest->height / 2, nearest->height / 2));
    const double stay = -std::log1p(-random.uniform()) / scenario::kAttractionLeaveRate;
    scenario::Action go;
    go.agent = static_cast<int>(a);
    go.kind = scenario::Action::Kind::go_to_pose;
    go.pose = {spot.x(), spot.y(), core::direction_to(self.position, spot)};
    go.pointer = "attraction: " + nearest->name;
    scenario::Action linger = go;
    linger.kind = scenario::Action::Kind::wait_duration;
    linger.value = stay;
    const scenario::Action visit[] = {go, linger};
    interrupt(state, static_cast<int>(a), visit);
    emit(model, state, model.agents[a].id, events::Attracted{nearest->name, spot.x(), spot.y(), stay});
  }
}

}  // namespace hrisim::sim
