#include "sim/attractions.hpp"

#include <gtest/gtest.h>

#include "sim/session.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

/// Ana walks from (1, 2) to (9, 2) past a kiosk at (5, 3.5), 1 m × 1 m, of the given strength, placed
/// `far` metres further north.
std::shared_ptr<const scenario::Model> kiosk(double strength, double far = 0.0) {
  return testing::load_valid(testing::room_scenario(json::parse(R"({
    "time_limit": 300,
    "attractions": {"kiosk": {"x": 5, "y": )" + std::to_string(3.5 + far) + R"(, "width": 1, "height": 1, "strength": )" + std::to_string(strength) + R"(}},
    "humans": [{"id": "ana", "start": {"x": 1, "y": 2}, "preferred_speed": 1.2}],
    "steps": [{"name": "walk", "actions": [{"agent": "ana", "goto": {"pose": {"x": 9, "y": 2}}}]}]})")));
}

struct Walk {
  std::vector<const Event*> attracted;
  double seconds_in_the_kiosk = 0.0;
  double arrived = -1.0;
};

Walk walk_past(const std::shared_ptr<const scenario::Model>& model, Session& session) {
  Walk walk;
  while (!session.state().finished) {
    session.tick();
    const Vec2 p = session.state().agents[0].position;
    if (std::abs(p.x() - model->attractions[0].centre.x()) <= 0.75 && std::abs(p.y() - model->attractions[0].centre.y()) <= 0.75) {
      walk.seconds_in_the_kiosk += model->dt;
    }
  }
  for (const Event& event : session.state().events) {
    if (event.is<sim::events::Attracted>()) walk.attracted.push_back(&event);
    if (event.is<sim::events::StepFinished>()) walk.arrived = event.time;
  }
  return walk;
}

TEST(Attractions, AStrongOneDrawsAPasserByInForAWhileThenTheyGoOn) {
  const auto model = kiosk(50.0);  // 0.02 × 50 = 1 per second at the centre: she turns aside at once
  Session session(model, 1);
  const Walk walk = walk_past(model, session);
  ASSERT_FALSE(walk.attracted.empty());
  const Event& first = *walk.attracted.front();
  const auto& attracted = *first.as<events::Attracted>();
  EXPECT_EQ(attracted.attraction, "kiosk");
  EXPECT_LE(std::abs(attracted.x - 5.0), 0.5) << "a point of the area";
  EXPECT_LE(std::abs(attracted.y - 3.5), 0.5);
  EXPECT_GT(walk.seconds_in_the_kiosk, 5.0) << "she stays a while";
  EXPECT_GT(walk.arrived, 0.0) << "and reaches her goal afterwards (the step ends)";
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
}

TEST(Attractions, NoneWithoutStrengthOrBeyondSevenMetres) {
  for (const auto& model : {kiosk(0.0), kiosk(50.0, 7.0)}) {
    Session session(model, 1);
    const Walk walk = walk_past(model, session);
    EXPECT_TRUE(walk.attracted.empty());
    EXPECT_LT(walk.arrived, 10.0) << "8 m at 1.2 m/s, straight on";
  }
}

// Mean stay 1 / 0.03 s ≈ 33 s: over 20 seeds the first stays' mean lands within three standard errors.
TEST(Attractions, StaysAreDrawnWithTheirMeanAndFollowTheSeed) {
  const auto model = kiosk(50.0);
  double sum = 0.0;
  std::vector<double> first_times;
  for (std::uint64_t seed = 1; seed <= 20; ++seed) {
    Session session(model, seed);
    const Walk walk = walk_past(model, session);
    ASSERT_FALSE(walk.attracted.empty());
    sum += walk.attracted.front()->as<events::Attracted>()->stay;
    first_times.push_back(walk.attracted.front()->time);
  }
  const double mean = 1.0 / scenario::kAttractionLeaveRate;
  EXPECT_NEAR(sum / 20.0, mean, 3.0 * mean / std::sqrt(20.0));
  Session again(model, 1);
  EXPECT_EQ(walk_past(model, again).attracted.front()->time, first_times[0]) << "the same seed, the same draws";
}

}  // namespace
}  // namespace hrisim::sim
