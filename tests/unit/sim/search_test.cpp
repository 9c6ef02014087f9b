// The search controller (seed 000's apartment search): rooms in order of the person's presence
// probability, or nearest first; a person is found by their face only; the episode ends when found,
// with time_to_find and success; otherwise the robot goes round the rooms again.
#include <gtest/gtest.h>

#include "episode/episode.hpp"
#include "metrics/episode_metrics.hpp"
#include "scenario/load.hpp"
#include "sim/session.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using nlohmann::json;

/// Two rooms parted by a wall at x = 5 with a door at y 4–6: ARTOS starts in the west one; Ada stands
/// all day in the east one at (8.5, 5), facing `ada_faces` (pi: the east room's lookout).
json two_rooms(const std::string& strategy, double ada_faces, double time_limit = 120) {
  json document = testing::room_scenario(json::parse(R"({
    "world": {"bounds": {"min": [-0.5, -0.5], "max": [10.5, 10.5]},
              "walls": [{"from": [0, 0], "to": [10, 0]}, {"from": [10, 0], "to": [10, 10]}, {"from": [10, 10], "to": [0, 10]},
                        {"from": [0, 10], "to": [0, 0]}, {"from": [5, 0], "to": [5, 4]}, {"from": [5, 6], "to": [5, 10]}],
              "obstacles": []},
    "locations": {"west_look": {"x": 2.5, "y": 5}, "east_look": {"x": 6.5, "y": 5}, "west_spot": {"x": 2.5, "y": 8.5},
                  "east_spot": {"x": 8.5, "y": 5, "theta": )" + std::to_string(ada_faces) + R"(}},
    "clock": {"start": "09:00"},
    "rooms": {"west": {"spots": ["west_spot"], "lookout": "west_look"}, "east": {"spots": ["east_spot"], "lookout": "east_look"}},
    "daily_schedules": {"ada": {"presence": [{"hours": [0, 24], "rooms": {"east": 1}}]}},
    "humans": [{"id": "ada", "start": {"x": 8.5, "y": 5, "theta": )" + std::to_string(ada_faces) + R"(}, "daily_schedule": "ada"}],
    "robots": [{"id": "artos", "model": "artos", "start": {"x": 1, "y": 5},
                "controller": {"type": "search", "person": "ada", "strategy": ")" + strategy + R"("},
                "people_detector": {"field_of_view": 1.0, "range": 8}}]
  })"));
  document["time_limit"] = time_limit;
  return document;
}

struct Search {
  std::vector<std::string> rooms;  ///< in the order the robot looked into them
  std::optional<double> found_at;
  sim::Termination termination = sim::Termination::none;
  std::map<std::string, metrics::MetricValue> metrics;
};

Search run(const json& document, std::uint64_t seed = 1) {
  const auto model = testing::load_valid(document);
  episode::Episode episode(model, seed);
  episode.run();
  Search search;
  for (const Event& event : episode.session().state().events) {
    if (event.subject != "artos") continue;
    if (const auto* room = event.as<events::SearchRoom>()) search.rooms.push_back(room->room);
    if (const auto* found = event.as<events::PersonFound>()) {
      search.found_at = event.time;
      EXPECT_EQ(found->person, "ada");
      EXPECT_EQ(found->room, "east");
      EXPECT_LE(found->range, sensors::kFaceRange + 0.25) << "within the face range, give or take the detector's noise";
    }
  }
  search.termination = episode.session().state().termination;
  for (const metrics::MetricValue& value : metrics::compute_episode_metrics(episode.recording())) search.metrics[value.key] = value;
  return search;
}

TEST(Search, ByPresenceTheMostLikelyRoomComesFirst) {
  Search presence = run(two_rooms("presence", 3.14159));
  ASSERT_FALSE(presence.rooms.empty());
  EXPECT_EQ(presence.rooms.front(), "east") << "she is in the east room all day";
  ASSERT_TRUE(presence.found_at);
  EXPECT_EQ(presence.termination, sim::Termination::goal);
  EXPECT_DOUBLE_EQ(*presence.metrics["time_to_find"].value, *presence.found_at);
  EXPECT_EQ(presence.metrics["success"].value, 1.0);

  Search sweep = run(two_rooms("sweep", 3.14159));
  ASSERT_GE(sweep.rooms.size(), 2u);
  EXPECT_EQ(sweep.rooms[0], "west") << "the nearest room first";
  EXPECT_EQ(sweep.rooms[1], "east");
  ASSERT_TRUE(sweep.found_at);
  EXPECT_GT(*sweep.found_at, *presence.found_at + 10.0) << "a look around the west room costs time";
  EXPECT_GT(*sweep.metrics["path_length"].value, *presence.metrics["path_length"].value);
}

TEST(Search, AFaceTurnedAwayIsNotFoundAndTheRobotGoesRoundAgain) {
  Search search = run(two_rooms("presence", 0.0));  // her back to the east room's lookout
  EXPECT_FALSE(search.found_at);
  EXPECT_EQ(search.termination, sim::Termination::timeout);
  ASSERT_GE(search.rooms.size(), 3u);
  EXPECT_EQ(search.rooms[0], "east");
  EXPECT_EQ(search.rooms[1], "west");
  EXPECT_EQ(search.rooms[2], "east") << "all rooms looked into: it starts over";
  EXPECT_FALSE(search.metrics["time_to_find"].value);
  EXPECT_EQ(search.metrics["time_to_find"].null_reason, "the robot never saw the person's face");
  EXPECT_EQ(search.metrics["success"].value, 0.0);
}

TEST(Search, TheSameSeedGivesTheSameSearch) {
  const auto model = testing::load_valid(two_rooms("sweep", 3.14159));
  Session first(model, 4), second(model, 4);
  for (int tick = 0; tick < 1200 && !first.state().finished; ++tick) {
    first.tick();
    second.tick();
  }
  EXPECT_EQ(first.state_hash(), second.state_hash());
}

TEST(Search, WhatTheSearchNeedsIsChecked) {
  json document = two_rooms("presence", 0.0);
  document["robots"][0]["controller"]["person"] = "bo";
  EXPECT_EQ(testing::error_at(document, "/robots/0/controller/person"), "the search controller looks for a human of the scenario; 'bo' is none");
  document = two_rooms("presence", 0.0);
  document["humans"][0].erase("daily_schedule");
  EXPECT_EQ(testing::error_at(document, "/robots/0/controller/strategy"),
            "searching by presence needs 'ada' to live by a daily schedule (or use \"strategy\": \"sweep\")");
  document = two_rooms("sweep", 0.0);
  document["robots"][0].erase("people_detector");
  EXPECT_EQ(testing::error_at(document, "/robots/0/controller"), "the search controller finds people with the robot's people_detector: give the robot one");
  document = two_rooms("sweep", 0.0);
  document["rooms"]["west"].erase("lookout");
  EXPECT_EQ(testing::error_at(document, "/rooms/west"), "the search controller looks into every room from its lookout: give 'west' one");
}

}  // namespace
}  // namespace hrisim::sim
