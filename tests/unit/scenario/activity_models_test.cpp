// Activity models as the loader reads them: postures come from the motions themselves, and a chain is
// refused, at the value at fault, when it asks a body for what it cannot do next, traps a person, or
// does not add up.
#include <gtest/gtest.h>

#include "scenario/activity_models.hpp"
#include "scenario/load.hpp"
#include "support/scenarios.hpp"

namespace hrisim::scenario {
namespace {

using nlohmann::json;

/// The room with two places and a person living by `model` (merged over a valid office worker's).
json living_room(const json& model_patch) {
  json model = json::parse(R"({
    "start": "stand",
    "activities": {"stand": {"wait": [1, 2]}, "walk": {"walk": ["desk", "window"]}, "sit_down": {"motion": "sit_down"},
                   "sit": {"wait": [5, 10]}, "stand_up": {"motion": "stand_up"}},
    "transitions": {"stand": {"walk": 0.5, "sit_down": 0.5}, "walk": {"stand": 1}, "sit_down": {"sit": 1},
                    "sit": {"stand_up": 1}, "stand_up": {"stand": 1}}})");
  if (model_patch.is_object()) model.merge_patch(model_patch);  // {} is null to nlohmann, and null replaces all
  return testing::room_scenario({{"locations", {{"desk", {{"x", 2}, {"y", 2}}}, {"window", {{"x", 8}, {"y", 8}}}}},
                                 {"activity_models", json::object({{"office", model}})},
                                 {"humans", {{{"id", "ada"}, {"start", {{"x", 2}, {"y", 8}}}, {"activity_model", "office"}}}}});
}

std::vector<core::ValidationError> errors_of(const json& document) { return load_scenario(document, {}).errors; }

TEST(ActivityModels, PosturesAreWhereTheMotionsLeaveTheBody) {
  const auto posture = [](const char* name, bool at_end) {
    const humans::MotionClip& clip = *humans::builtin_motion(name);
    return posture_at(clip, at_end ? clip.duration() : 0.0);
  };
  EXPECT_EQ(posture("sit_down", false), Posture::standing);
  EXPECT_EQ(posture("sit_down", true), Posture::seated);
  EXPECT_EQ(posture("stand_up", false), Posture::seated);
  EXPECT_EQ(posture("fall", true), Posture::lying);
  EXPECT_EQ(posture("lie", false), Posture::lying);
  EXPECT_EQ(posture("get_up", true), Posture::standing);
  EXPECT_EQ(posture("wave", true), Posture::standing);
}

TEST(ActivityModels, AValidModelIsReadWithItsChain) {
  const auto model = testing::load_valid(living_room({}));
  ASSERT_TRUE(model);
  ASSERT_EQ(model->activity_models.size(), 1u);
  const ActivityModel& office = model->activity_models[0];
  EXPECT_EQ(office.activities[office.start].name, "stand");
  EXPECT_EQ(model->agents[0].activity_model, 0);
  int walk = -1, sit_down = -1;
  for (std::size_t a = 0; a < office.activities.size(); ++a) {
    if (office.activities[a].name == "walk") walk = static_cast<int>(a);
    if (office.activities[a].name == "sit_down") sit_down = static_cast<int>(a);
  }
  EXPECT_EQ(office.activities[walk].locations.size(), 2u);
  EXPECT_DOUBLE_EQ(office.transitions[office.start][walk], 0.5);
  EXPECT_DOUBLE_EQ(office.activities[sit_down].min_duration, humans::builtin_motion("sit_down")->duration());
}

TEST(ActivityModels, ASeatedPersonMustStandUpBeforeWalking) {
  const std::string message = testing::error_at(living_room({{"transitions", {{"sit", {{"walk", 1}, {"stand_up", nullptr}}}}}}),
                                       "/activity_models/office/transitions/sit/walk");
  EXPECT_NE(message.find("'walk' begins standing, but 'sit' can leave the person seated"), std::string::npos) << message;
}

TEST(ActivityModels, AFallenPersonGetsUpBeforeWalking) {
  json patch = {{"activities", {{"fall", {{"motion", "fall"}}}, {"lie", {{"motion", "lie"}, {"duration", {3, 6}}}},
                                {"get_up", {{"motion", "get_up"}}}}},
                {"transitions", {{"stand", {{"walk", 0.5}, {"sit_down", 0.4}, {"fall", 0.1}}},
                                 {"fall", {{"lie", 1}}}, {"lie", {{"walk", 1}}}, {"get_up", {{"stand", 1}}}}}};
  EXPECT_NE(testing::error_at(living_room(patch), "/activity_models/office/transitions/lie/walk").find("lying"), std::string::npos);
  patch["transitions"]["lie"] = {{"get_up", 1}};
  EXPECT_TRUE(errors_of(living_room(patch)).empty());
}

TEST(ActivityModels, AnActivityThatCannotBeLeftIsNamed) {
  // Sitting for ever: the row goes back to itself only.
  EXPECT_NE(testing::error_at(living_room({{"transitions", {{"sit", {{"sit", 1}, {"stand_up", nullptr}}}}}}), "/activity_models/office/transitions/sit")
                .find("'sit' cannot be left"),
            std::string::npos);
  // A pair of activities that only lead to each other never returns to the start.
  json patch = {{"activities", {{"lie", {{"motion", "lie"}, {"duration", 2}}}, {"fall", {{"motion", "fall"}}}}},
                {"transitions", {{"stand", {{"walk", 0.5}, {"sit_down", 0.4}, {"fall", 0.1}}}, {"fall", {{"lie", 1}}}, {"lie", {{"lie", 0.5}, {"fall", 0.5}}}}}};
  const std::string message = testing::error_at(living_room(patch), "/activity_models/office/transitions/lie");
  EXPECT_NE(message.find("nothing after it leads back to 'stand'"), std::string::npos) << message;
  // An activity without a row at all.
  EXPECT_NE(testing::error_at(living_room({{"transitions", {{"stand_up", nullptr}}}}), "/activity_models/office/transitions")
                .find("'stand_up' has no transitions"),
            std::string::npos);
}

TEST(ActivityModels, BadValuesAreNamedWhereTheyStand) {
  EXPECT_NE(testing::error_at(living_room({{"transitions", {{"stand", {{"walk", 0.5}, {"sit_down", 0.4}}}}}}), "/activity_models/office/transitions/stand")
                .find("add up to 0.9"),
            std::string::npos);
  EXPECT_NE(testing::error_at(living_room({{"activities", {{"wave", {{"motion", "juggle"}}}}}}), "/activity_models/office/activities/wave/motion")
                .find("unknown motion 'juggle'"),
            std::string::npos);
  EXPECT_NE(testing::error_at(living_room({{"activities", {{"walk", {{"walk", {"desk", "attic"}}}}}}}), "/activity_models/office/activities/walk/walk/1")
                .find("unknown location 'attic'"),
            std::string::npos);
  EXPECT_NE(testing::error_at(living_room({{"activities", {{"idle", {{"motion", "idle"}}}}}, {"transitions", {{"idle", {{"stand", 1}}}}}}),
                     "/activity_models/office/activities/idle")
                .find("loops: give a 'duration'"),
            std::string::npos);
  EXPECT_NE(testing::error_at(living_room({{"transitions", {{"stand", {{"dance", 0.5}, {"sit_down", nullptr}}}}}}), "/activity_models/office/transitions/stand/dance")
                .find("not one of the model's activities"),
            std::string::npos);
  EXPECT_NE(testing::error_at(living_room({{"start", "nap"}}), "/activity_models/office/start").find("'nap'"), std::string::npos);
  EXPECT_NE(testing::error_at(living_room({{"transitions_by_type", {{"robot", json::object()}}}}), "/activity_models/office/transitions_by_type/robot")
                .find("not a type of person"),
            std::string::npos);
  EXPECT_NE(testing::error_at(living_room({{"activities", {{"stand", {{"wait", {3, 1}}}}}}}), "/activity_models/office/activities/stand/wait")
                .find("shorter"),
            std::string::npos);
  json unknown = living_room({});
  unknown["humans"][0]["activity_model"] = "gardener";
  EXPECT_NE(testing::error_at(unknown, "/humans/0/activity_model").find("unknown activity model 'gardener'"), std::string::npos);
  json both = living_room({});
  both["activity_models"]["office"]["activities"]["stand"] = {{"wait", 1}, {"walk", {"desk"}}};
  EXPECT_FALSE(errors_of(both).empty()) << "an activity is one thing";
}

TEST(ActivityModels, ATypeOfPersonHasItsOwnChain) {
  json document = living_room({{"transitions_by_type", {{"child", {{"stand", {{"walk", 0.9}, {"sit_down", 0.1}}}, {"walk", {{"stand", 1}}}, {"sit_down", {{"sit", 1}}},
                                                                   {"sit", {{"stand_up", 1}}}, {"stand_up", {{"stand", 1}}}}}}}});
  const auto model = testing::load_valid(document);
  ASSERT_TRUE(model);
  const ActivityModel& office = model->activity_models[0];
  EXPECT_NE(&office.transitions_for("child"), &office.transitions);
  EXPECT_EQ(&office.transitions_for("elder"), &office.transitions);
  // A type's chain is checked like the default one.
  document["activity_models"]["office"]["transitions_by_type"]["child"]["sit"] = {{"walk", 1}};
  EXPECT_FALSE(testing::error_at(document, "/activity_models/office/transitions_by_type/child/sit/walk").empty());
}

}  // namespace
}  // namespace hrisim::scenario
