#include "sim/queues.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "scenario/load.hpp"
#include "sim/session.hpp"
#include "support/events.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

/// A counter against the room's north wall: its line runs south from (2, 8.5) along x = 2. Four people
/// come from the east, nearest first; each queues once.
json counter(double service_time) {
  return testing::room_scenario(json::parse(R"({
    "queues": {"counter": {"x": 2, "y": 8.5, "theta": 1.5708, "service_time": )" + std::to_string(service_time) + R"(}},
    "humans": [{"id": "ana", "start": {"x": 4, "y": 7}}, {"id": "ben", "start": {"x": 6, "y": 6}},
               {"id": "cai", "start": {"x": 8, "y": 5}}, {"id": "dee", "start": {"x": 9, "y": 2}}],
    "steps": [{"name": "queue", "actions": [{"agent": "ana", "queue": "counter"}, {"agent": "ben", "queue": "counter"},
                                             {"agent": "cai", "queue": "counter"}, {"agent": "dee", "queue": "counter"}]}]})"));
}

using testing::events_of;

TEST(Queues, PeopleLineUpInTheOrderTheyCameAndAreServedOneAtATime) {
  const auto model = testing::load_valid(counter(4.0));
  ASSERT_TRUE(model);
  Session session(model, 1);
  // Everyone has joined and stands at their place, facing the head.
  while (session.time() < 20.0 && events_of<sim::events::QueueJoined>(session).size() < 4) session.tick();
  for (int settle = 0; settle < 300; ++settle) session.tick();
  const auto joined = events_of<sim::events::QueueJoined>(session);
  ASSERT_EQ(joined.size(), 4u);
  std::vector<std::string> order;
  for (const Event* event : joined) order.push_back(event->subject);
  EXPECT_EQ(order, (std::vector<std::string>{"ana", "ben", "cai", "dee"})) << "the nearest reach the end of the line first";
  const scenario::Queue& queue = model->queues[0];
  const std::vector<int>& line = session.state().queues[0].line;
  const int served_before = static_cast<int>(events_of<sim::events::Served>(session).size());
  for (std::size_t place = 0; place < line.size(); ++place) {
    const AgentState& person = session.state().agents[line[place]];
    EXPECT_LT((person.position - queue.place(static_cast<int>(place) + served_before).position()).norm(), 0.5 + 0.8 * served_before)
        << model->agents[line[place]].id << " stands in line";
  }
  while (!session.state().finished) session.tick();
  EXPECT_EQ(session.state().termination, sim::Termination::scenario_end);
  const auto served = events_of<sim::events::Served>(session);
  ASSERT_EQ(served.size(), 4u);
  for (std::size_t i = 0; i < served.size(); ++i) EXPECT_EQ(served[i]->subject, order[i]) << "served in the order they joined";
  for (std::size_t i = 1; i < served.size(); ++i) {
    EXPECT_GT(served[i]->time - served[i - 1]->time, 0.5) << "one at a time: the next steps up 0.8 m, then is served";
  }
  EXPECT_TRUE(session.state().queues[0].line.empty());
}

// Gamma(2, mean / 2) has mean `mean` and standard deviation mean / √2: over 40 services the mean
// lands within three standard errors.
TEST(Queues, ServiceTimesAreDrawnWithTheirMeanAndDifferBySeed) {
  json scenario = counter(6.0);
  scenario["time_limit"] = 600;
  std::vector<double> gaps;
  std::vector<double> first_services;
  for (const int seed : {1, 2, 3, 4, 5, 6, 7, 8, 9, 10}) {
    const auto model = testing::load_valid(scenario);
    Session session(model, static_cast<std::uint64_t>(seed));
    while (!session.state().finished) session.tick();
    const auto served = events_of<sim::events::Served>(session);
    ASSERT_EQ(served.size(), 4u);
    first_services.push_back(served[0]->time);
    // From the moment each stands at the head (the previous one leaves, then 0.8 m to walk) to served.
    for (std::size_t i = 1; i < served.size(); ++i) gaps.push_back(served[i]->time - served[i - 1]->time);
  }
  double mean = 0.0;
  for (const double gap : gaps) mean += gap;
  mean /= static_cast<double>(gaps.size());
  // Each gap is a service plus the step up to the head (about a second).
  EXPECT_NEAR(mean, 6.0 + 1.0, 3.0 * 6.0 / std::numbers::sqrt2 / std::sqrt(static_cast<double>(gaps.size())) + 0.5);
  EXPECT_NE(first_services[0], first_services[1]) << "another seed, other service times";
  const auto model = testing::load_valid(scenario);
  Session again(model, 1);
  while (!again.state().finished) again.tick();
  EXPECT_EQ(events_of<sim::events::Served>(again)[0]->time, first_services[0]) << "the same seed, the same times";
}

TEST(Queues, SomeoneLeavingTheLineLetsThoseBehindMoveUp) {
  const auto model = testing::load_valid(counter(30.0));
  Session session(model, 1);
  while (session.time() < 25.0) session.tick();
  ASSERT_EQ(session.state().queues[0].line.size(), 4u);
  session.remove_agent(session.agent_id("ben"));
  for (int settle = 0; settle < 300; ++settle) session.tick();
  const std::vector<int>& line = session.state().queues[0].line;
  ASSERT_EQ(line.size(), 3u);
  EXPECT_EQ(model->agents[line[1]].id, "cai");
  EXPECT_LT((session.state().agents[line[1]].position - model->queues[0].place(1).position()).norm(), 0.3) << "cai stepped up into ben's place";
}

TEST(Queues, AQueueIsCheckedWhereItIsWritten) {
  json unknown = counter(1.0);
  unknown["steps"][0]["actions"][0]["queue"] = "bakery";
  const scenario::LoadResult bad = scenario::load_scenario(unknown, {});
  ASSERT_FALSE(bad.errors.empty());
  EXPECT_EQ(bad.errors[0].pointer, "/steps/0/actions/0/queue");
  EXPECT_NE(bad.errors[0].message.find("unknown queue 'bakery'"), std::string::npos) << bad.errors[0].message;
  json in_table = counter(1.0);
  in_table["queues"]["counter"]["x"] = 5;
  in_table["queues"]["counter"]["y"] = 5;
  const scenario::LoadResult blocked = scenario::load_scenario(in_table, {});
  ASSERT_FALSE(blocked.errors.empty());
  EXPECT_EQ(blocked.errors[0].pointer, "/queues/counter");
}

}  // namespace
}  // namespace hrisim::sim
