// People living by an activity model: after the choreography, they go from activity to activity as
// the chain says — sitting down before sitting, standing up before walking on — with the frequencies
// of its rows, drawn from their own seeded stream, and the episode runs to its time limit.
#include <gtest/gtest.h>

#include <map>
#include <set>

#include "sim/session.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

json office_scenario(double time_limit, const json& steps = json::array()) {
  json document = testing::room_scenario(
      {{"time_limit", time_limit},
       {"locations", {{"desk", {{"x", 2}, {"y", 2}}}, {"window", {{"x", 8}, {"y", 8}}}}},
       {"activity_models", json::object({{"office", json::parse(R"({
          "start": "stand",
          "activities": {"stand": {"wait": [1, 2]}, "walk": {"walk": ["desk", "window"]}, "wave": {"motion": "wave"},
                         "sit_down": {"motion": "sit_down"}, "sit": {"wait": [3, 6]}, "stand_up": {"motion": "stand_up"}},
          "transitions": {"stand": {"walk": 0.5, "sit_down": 0.3, "wave": 0.2}, "walk": {"stand": 1}, "wave": {"stand": 1},
                          "sit_down": {"sit": 1}, "sit": {"stand_up": 1}, "stand_up": {"stand": 1}}})")}})},
       {"humans", {{{"id", "ada"}, {"start", {{"x", 2}, {"y", 8}}}, {"activity_model", "office"}},
                   {{"id", "bo"}, {"start", {{"x", 8}, {"y", 2}}}, {"activity_model", "office"}}}}});
  document["steps"] = steps;
  return document;
}

struct Started {
  double time;
  std::string activity, location;
};

std::vector<Started> activities_of(const Session& session, const std::string& person) {
  std::vector<Started> started;
  for (const Event& event : session.state().events) {
    const auto* activity = event.as<events::ActivityStarted>();
    if (activity && event.subject == person) {
      started.push_back({event.time, activity->activity, activity->location.value_or("")});
    }
  }
  return started;
}

TEST(Activities, PeopleFollowTheChainAndWalkWhereItSends) {
  Session session(testing::load_valid(office_scenario(600)), 3);
  const int ada = session.index_of(session.agent_id("ada"));
  std::map<std::string, Vec2> places{{"desk", {2, 2}}, {"window", {8, 8}}};
  std::string walking_to;
  while (!session.state().finished) {
    const std::size_t before = session.state().events.size();
    session.tick();
    for (std::size_t e = before; e < session.state().events.size(); ++e) {
      const Event& event = session.state().events[e];
      if (!event.is<sim::events::ActivityStarted>() || event.subject != "ada") continue;
      // A walk is over when the next activity starts: she is at the place it drew.
      if (!walking_to.empty()) {
        EXPECT_LT((session.state().agents[ada].position - places.at(walking_to)).norm(), 0.5) << walking_to;
      }
      const auto& activity = *event.as<events::ActivityStarted>();
      walking_to = activity.activity == "walk" ? activity.location.value() : "";
    }
  }
  EXPECT_EQ(session.state().termination, sim::Termination::timeout) << "people living on keep the episode going";
  const std::vector<Started> started = activities_of(session, "ada");
  ASSERT_GT(started.size(), 40u);
  EXPECT_EQ(started[0].activity, "stand");
  EXPECT_EQ(started[0].time, 0.0);
  const std::map<std::string, std::set<std::string>> allowed{{"stand", {"walk", "sit_down", "wave"}}, {"walk", {"stand"}}, {"wave", {"stand"}},
                                                             {"sit_down", {"sit"}}, {"sit", {"stand_up"}}, {"stand_up", {"stand"}}};
  std::set<std::string> seen;
  for (std::size_t i = 1; i < started.size(); ++i) {
    EXPECT_TRUE(allowed.at(started[i - 1].activity).contains(started[i].activity)) << started[i - 1].activity << " -> " << started[i].activity;
    seen.insert(started[i].activity);
    if (started[i].activity == "sit") {
      // Sitting down takes the motion's whole length.
      EXPECT_NEAR(started[i].time - started[i - 1].time, humans::builtin_motion("sit_down")->duration(), 2.0 / 60);
    }
  }
  EXPECT_EQ(seen.size(), 6u) << "every activity comes up in 10 minutes";
}

TEST(Activities, TheRowsFrequenciesComeOut) {
  // After "stand": walk 0.5, sit_down 0.3, wave 0.2. Pearson's chi-squared over two people's hours,
  // two degrees of freedom: above 13.8 one time in a thousand.
  Session session(testing::load_valid(office_scenario(3600)), 11);
  while (!session.state().finished) session.tick();
  std::map<std::string, double> counts;
  double total = 0;
  for (const char* person : {"ada", "bo"}) {
    const std::vector<Started> started = activities_of(session, person);
    for (std::size_t i = 1; i < started.size(); ++i) {
      if (started[i - 1].activity != "stand") continue;
      counts[started[i].activity] += 1;
      total += 1;
    }
  }
  ASSERT_GT(total, 300);
  double chi2 = 0;
  for (const auto& [activity, p] : std::map<std::string, double>{{"walk", 0.5}, {"sit_down", 0.3}, {"wave", 0.2}}) {
    chi2 += (counts[activity] - p * total) * (counts[activity] - p * total) / (p * total);
  }
  EXPECT_LT(chi2, 13.8) << "walk " << counts["walk"] << ", sit_down " << counts["sit_down"] << ", wave " << counts["wave"] << " of " << total;
}

TEST(Activities, TheChoreographyComesFirstAndTheSameSeedGivesTheSameLife) {
  const json steps = json::parse(R"([{"name": "meet", "actions": [{"agent": "ada", "goto": {"location": "window"}}, {"agent": "bo", "wait": {"duration": 4}}]}])");
  const auto model = testing::load_valid(office_scenario(120, steps));
  Session first(model, 5), second(model, 5), other(model, 6);
  while (!first.state().finished) {
    first.tick();
    second.tick();
    other.tick();
  }
  const std::vector<Started> ada = activities_of(first, "ada");
  ASSERT_FALSE(ada.empty());
  double step_finished = -1;
  for (const Event& event : first.state().events) {
    if (event.is<sim::events::StepFinished>()) step_finished = event.time;
  }
  EXPECT_GE(step_finished, 4.0);
  EXPECT_EQ(ada[0].time, step_finished) << "her life starts when the choreography is over";
  EXPECT_EQ(first.state_hash(), second.state_hash());
  std::string life, other_life;
  for (const Started& s : ada) life += s.activity + s.location + " ";
  for (const Started& s : activities_of(other, "ada")) other_life += s.activity + s.location + " ";
  EXPECT_NE(life, other_life) << "another seed, another life";
}

}  // namespace
}  // namespace hrisim::sim
