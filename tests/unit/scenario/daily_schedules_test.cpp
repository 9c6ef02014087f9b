// Daily schedules as the loader reads them: a clock, rooms made of locations, and per person the
// probability of being in each room per hour; refused at the value at fault when an hour is missing
// or twice, a row does not add up to 1, a room or model is unknown, or a room's model would walk out.
#include <gtest/gtest.h>

#include "scenario/daily_schedules.hpp"
#include "scenario/load.hpp"
#include "support/scenarios.hpp"

namespace hrisim::scenario {
namespace {

using nlohmann::json;

/// Two rooms, a sitting model for the study, and Ada's day (merged over a valid one).
json home(const json& patch = json::object()) {
  json document = testing::room_scenario(json::parse(R"({
    "locations": {"desk": {"x": 2, "y": 2}, "sofa": {"x": 8, "y": 8}, "study_door": {"x": 3, "y": 3}},
    "clock": {"start": "06:30", "speed": 60},
    "rooms": {"study": {"spots": ["desk"], "lookout": "study_door"}, "lounge": {"spots": ["sofa"]}},
    "activity_models": {"sitting": {"start": "stand", "activities": {"stand": {"wait": 1}, "sit_down": {"motion": "sit_down"},
                                    "sit": {"wait": 5}, "stand_up": {"motion": "stand_up"}},
                                    "transitions": {"stand": {"sit_down": 1}, "sit_down": {"sit": 1}, "sit": {"stand_up": 1}, "stand_up": {"stand": 1}}}},
    "daily_schedules": {"ada": {"stay": [5, 20], "activities": {"study": "sitting"},
                                "presence": [{"hours": [0, 9], "rooms": {"lounge": 1}},
                                             {"hours": [9, 24], "rooms": {"study": 0.75, "lounge": 0.25}}]}},
    "humans": [{"id": "ada", "start": {"x": 5, "y": 8}, "daily_schedule": "ada"}]})"));
  document.merge_patch(patch);
  return document;
}

TEST(DailySchedules, AValidDayIsReadHourByHour) {
  const auto model = testing::load_valid(home());
  ASSERT_TRUE(model);
  ASSERT_TRUE(model->clock);
  EXPECT_DOUBLE_EQ(model->clock->start, 6.5 * 3600);
  EXPECT_DOUBLE_EQ(model->clock->speed, 60);
  ASSERT_EQ(model->rooms.size(), 2u);
  EXPECT_EQ(model->rooms[0].name, "lounge");  // object keys come sorted
  EXPECT_EQ(model->locations[model->rooms[1].lookout].name, "study_door");
  EXPECT_EQ(model->rooms[0].lookout, -1);
  const DailySchedule& ada = model->daily_schedules.at(0);
  EXPECT_DOUBLE_EQ(ada.min_stay, 5 * 60);
  EXPECT_DOUBLE_EQ(ada.max_stay, 20 * 60);
  EXPECT_EQ(ada.presence[8], (std::vector<double>{1.0, 0.0}));
  EXPECT_EQ(ada.presence[9], (std::vector<double>{0.25, 0.75}));
  EXPECT_EQ(ada.presence[23], (std::vector<double>{0.25, 0.75}));
  EXPECT_EQ(ada.activities, (std::vector<int>{-1, 0}));
  EXPECT_EQ(ada.rooms_by_presence(10), (std::vector<int>{1, 0}));
  EXPECT_EQ(model->agents[0].daily_schedule, 0);
}

TEST(DailySchedules, TheClockReadsTheTimeOfDay) {
  const Clock clock{6.5 * 3600, 60};
  EXPECT_EQ(format_time_of_day(time_of_day(clock, 0)), "06:30:00");
  EXPECT_EQ(format_time_of_day(time_of_day(clock, 90.5)), "08:00:30");
  EXPECT_EQ(format_time_of_day(time_of_day(clock, 1050)), "00:00:00");  // 17.5 h later: midnight
  EXPECT_EQ(day_of(clock, 1049.9), 0);
  EXPECT_EQ(day_of(clock, 1050), 1);
  EXPECT_EQ(format_time_of_day(time_of_day(clock, 1050 + 1440 * 2 + 61)), "01:01:00");
}

TEST(DailySchedules, EveryHourOnceAndRowsThatAddUpToOne) {
  EXPECT_EQ(testing::error_at(home({{"daily_schedules", {{"ada", {{"presence", json::array({{{"hours", {0, 9}}, {"rooms", {{"lounge", 1}}}},
                                                                                   {{"hours", {10, 24}}, {"rooms", {{"lounge", 1}}}}})}}}}}}),
                     "/daily_schedules/ada/presence"),
            "hour 9 (9:00–10:00) is in no period: cover the whole day");
  EXPECT_EQ(testing::error_at(home({{"daily_schedules", {{"ada", {{"presence", json::array({{{"hours", {0, 10}}, {"rooms", {{"lounge", 1}}}},
                                                                                   {{"hours", {9, 24}}, {"rooms", {{"lounge", 1}}}}})}}}}}}),
                     "/daily_schedules/ada/presence/1/hours"),
            "hour 9 is already covered by period 0");
  EXPECT_EQ(testing::error_at(home({{"daily_schedules", {{"ada", {{"presence", json::array({{{"hours", {0, 24}}, {"rooms", {{"lounge", 0.5}, {"study", 0.3}}}}})}}}}}}),
                     "/daily_schedules/ada/presence/0/rooms"),
            "the probabilities add up to 0.8, not 1");
  EXPECT_EQ(testing::error_at(home({{"daily_schedules", {{"ada", {{"presence", json::array({{{"hours", {24, 0}}, {"rooms", {{"lounge", 1}}}}})}}}}}}),
                     "/daily_schedules/ada/presence/0/hours"),
            "the period ends (hour 0) before it begins (hour 24)");
}

TEST(DailySchedules, RoomsModelsAndTheClockMustExist) {
  EXPECT_EQ(testing::error_at(home({{"daily_schedules", {{"ada", {{"presence", json::array({{{"hours", {0, 24}}, {"rooms", {{"attic", 1}}}}})}}}}}}),
                     "/daily_schedules/ada/presence/0/rooms/attic"),
            "unknown room 'attic'; the scenario's rooms are lounge, study");
  EXPECT_EQ(testing::error_at(home({{"daily_schedules", {{"ada", {{"activities", {{"study", "napping"}}}}}}}}), "/daily_schedules/ada/activities/study"),
            "unknown activity model 'napping'");
  EXPECT_EQ(testing::error_at(home({{"rooms", {{"study", {{"spots", {"desk", "bed"}}}}}}}), "/rooms/study/spots/1"), "unknown location 'bed'");
  EXPECT_EQ(testing::error_at(home({{"rooms", {{"study", {{"lookout", "hall"}}}}}}), "/rooms/study/lookout"), "unknown location 'hall'");
  EXPECT_EQ(testing::error_at(home({{"clock", nullptr}}), "/daily_schedules"), "daily schedules need the scenario's 'clock' (its start time of day and speed)");
  EXPECT_EQ(testing::error_at(home({{"clock", {{"start", "25:00"}}}}), "/clock/start"),
            "'25:00' is not a time of day: write HH:MM or HH:MM:SS (00:00 to 23:59:59)");
  EXPECT_EQ(testing::error_at(home({{"clock", {{"start", {"20:00", "08:00"}}}}}), "/clock/start"),
            "the latest start is earlier than the earliest: the clock does not run over midnight here");
  EXPECT_EQ(testing::error_at(home({{"clock", {{"start", {"08:00", "8h"}}}}}), "/clock/start/1"),
            "'8h' is not a time of day: write HH:MM or HH:MM:SS (00:00 to 23:59:59)");
  EXPECT_EQ(testing::error_at(home({{"humans", {{{"id", "ada"}, {"start", {{"x", 5}, {"y", 8}}}, {"daily_schedule", "bob"}}}}}), "/humans/0/daily_schedule"),
            "unknown daily schedule 'bob'");
  EXPECT_EQ(testing::error_at(home({{"daily_schedules", {{"ada", {{"stay", {30, 10}}}}}}}), "/daily_schedules/ada/stay"),
            "the longest stay is shorter than the shortest");
}

TEST(DailySchedules, ARoomsModelKeepsThePersonInTheRoom) {
  json document = home();
  document["activity_models"]["sitting"]["activities"]["leave"] = {{"walk", {"sofa"}}};
  document["activity_models"]["sitting"]["transitions"]["stand"] = {{"sit_down", 0.5}, {"leave", 0.5}};
  document["activity_models"]["sitting"]["transitions"]["leave"] = {{"stand", 1}};
  EXPECT_EQ(testing::error_at(document, "/daily_schedules/ada/activities/study"),
            "activity model 'sitting' walks ('leave'): a room's model keeps the person in the room");
}

TEST(DailySchedules, APersonLivesByAScheduleOrByAModelNotBoth) {
  json document = home();
  document["humans"][0]["activity_model"] = "sitting";
  EXPECT_EQ(testing::error_at(document, "/humans/0"),
            "human 'ada' has both an activity_model and a daily_schedule: a schedule chooses the model in each room, give one of them");
}

}  // namespace
}  // namespace hrisim::scenario
