#include "robots/description.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>

namespace hrisim::robots {
namespace {

using nlohmann::json;

double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }

json asset(const std::string& name) {
  std::ifstream file(std::string(HRISIM_SOURCE_DIR) + "/assets/robots/" + name + ".json");
  return json::parse(file);
}

TEST(RobotDescription, BuiltinsAreTheAssets) {
  EXPECT_EQ(builtin_robot_names(), (std::vector<std::string>{"artos", "hsr", "roman"}));
  for (const std::string name : {"artos", "hsr", "roman"}) {
    const LoadedRobot from_file = load_robot_description(asset(name));
    ASSERT_TRUE(from_file.errors.empty()) << name << ": " << from_file.errors.front().pointer << " "
                                          << from_file.errors.front().message;
    ASSERT_NE(builtin_robot(name), nullptr);
    EXPECT_EQ(builtin_robot(name)->name, name) << "a built-in robot is named by its file";
    EXPECT_EQ(builtin_robot(name)->joints.size(), from_file.description->joints.size());
  }
  EXPECT_EQ(builtin_robot("r2d2"), nullptr);
}

TEST(RobotDescription, HsrFollowsTheSeedsTables) {
  const auto hsr = builtin_robot("hsr");
  // Table 3.1: 43 cm across, 37 kg, 0.8 km/h; section 4.2: wheels of 0.04 m, 0.266 m apart.
  EXPECT_DOUBLE_EQ(hsr->footprint_radius, 0.215);
  EXPECT_DOUBLE_EQ(hsr->mass, 37.0);
  double link_mass = 0.0;
  for (const Link& link : hsr->links) link_mass += link.mass;
  EXPECT_NEAR(link_mass, 37.0, 1e-9);
  ASSERT_TRUE(hsr->drive);
  EXPECT_DOUBLE_EQ(hsr->drive->params.wheel_radius, 0.04);
  EXPECT_DOUBLE_EQ(hsr->drive->params.wheel_separation, 0.266);
  EXPECT_NEAR(hsr->drive->params.max_linear_speed * 3.6, 0.8, 1e-5);
  // Table 3.2's ranges, in degrees for revolute joints and metres for prismatic ones.
  const std::vector<std::tuple<std::string, double, double>> ranges{
      {"arm_roll_joint", -119.75, 220.02}, {"wrist_flex_joint", -110.01, 69.90}, {"arm_flex_joint", -150.11, 0.0},
      {"wrist_roll_joint", -110.01, 210.28}, {"base_roll_joint", -180.0, 180.0}, {"hand_motor_joint", -45.72, 71.04},
      {"head_pan_joint", -220.02, 100.27}, {"head_tilt_joint", -89.95, 29.29}};
  for (const auto& [name, lower, upper] : ranges) {
    const Joint& joint = hsr->joints[hsr->find_joint(name)];
    EXPECT_NEAR(degrees(*joint.limits.lower), lower, 1e-4) << name;
    EXPECT_NEAR(degrees(*joint.limits.upper), upper, 1e-4) << name;
  }
  const Joint& arm_lift = hsr->joints[hsr->find_joint("arm_lift_joint")];
  EXPECT_EQ(*arm_lift.limits.upper, 0.69);
  EXPECT_EQ(*hsr->joints[hsr->find_joint("torso_lift_joint")].limits.upper, 0.345);
  // The arm controller of section 4.2.2.3: five arm joints plus base roll.
  EXPECT_EQ(hsr->groups.at("arm"), (std::vector<std::string>{"arm_lift_joint", "arm_flex_joint", "arm_roll_joint",
                                                             "wrist_flex_joint", "wrist_roll_joint", "base_roll_joint"}));
  EXPECT_NE(hsr->find_sensor("base_scan"), nullptr);
  EXPECT_EQ(hsr->find_sensor("head_rgbd")->type, "rgbd_camera");
}

TEST(RobotDescription, ArtosAndRomanHaveTheSeedsParts) {
  const auto artos = builtin_robot("artos");
  EXPECT_TRUE(artos->drive);
  EXPECT_EQ(artos->groups.at("head").size(), 2u) << "pan-tilt camera";
  EXPECT_EQ(artos->find_sensor("laser")->type, "laser");
  const auto roman = builtin_robot("roman");
  EXPECT_FALSE(roman->drive);
  for (const std::string dc : {"torso_yaw_joint", "torso_pitch_joint", "neck_pan_joint", "neck_tilt_joint"}) {
    EXPECT_EQ(roman->joints[roman->find_joint(dc)].motor.kind, MotorKind::dc) << dc;
  }
  for (const std::string servo : {"left_eye_pan_joint", "left_eyelid_joint", "jaw_joint"}) {
    EXPECT_EQ(roman->joints[roman->find_joint(servo)].motor.kind, MotorKind::servo) << servo;
  }
  int cameras = 0, microphones = 0;
  for (const Sensor& sensor : roman->sensors) {
    cameras += sensor.type == "camera";
    microphones += sensor.type == "microphone";
  }
  EXPECT_EQ(cameras, 2);
  EXPECT_EQ(microphones, 6);
}

json minimal() {
  return {{"name", "cart"},
          {"links", json::array({{{"name", "base"}}, {{"name", "wheel"}}})},
          {"joints", json::array({{{"name", "spin"}, {"type", "continuous"}, {"parent", "base"}, {"child", "wheel"},
                                   {"motor", {{"kind", "dc"}, {"max_motor_velocity", 10.0}}}}})}};
}

std::vector<std::string> pointers(const LoadedRobot& loaded) {
  std::vector<std::string> result;
  for (const auto& error : loaded.errors) result.push_back(error.pointer);
  return result;
}

TEST(RobotDescription, EveryBrokenReferenceIsReportedWithItsPointer) {
  EXPECT_TRUE(load_robot_description(minimal()).errors.empty());
  json broken = minimal();
  broken["links"].push_back({{"name", "wheel"}});                       // duplicate link
  broken["joints"].push_back({{"name", "spin"}, {"type", "revolute"}, {"parent", "nowhere"}, {"child", "base"},
                              {"motor", {{"kind", "servo"}}}});          // duplicate, unknown parent, moves the root, no limits
  broken["groups"] = {{"arm", {"spin", "elbow"}}};                      // unknown joint
  broken["sensors"] = json::array({{{"name", "eye"}, {"type", "camera"}, {"link", "head"}}});  // unknown link
  broken["drive"] = {{"left_wheel", "spin"}, {"right_wheel", "ghost"}, {"wheel_radius", 0.1}, {"wheel_separation", 0.4},
                     {"max_linear_speed", 1.0}, {"max_angular_speed", 1.0}};
  const LoadedRobot loaded = load_robot_description(broken);
  EXPECT_EQ(loaded.description, nullptr);
  const auto found = pointers(loaded);
  for (const std::string expected : {"/links/2/name", "/joints/1/name", "/joints/1/parent", "/joints/1/child", "/joints/1",
                                     "/groups/arm/1", "/sensors/0/link", "/drive/right_wheel"}) {
    EXPECT_NE(std::find(found.begin(), found.end(), expected), found.end()) << expected;
  }
}

TEST(RobotDescription, SchemaErrorsComeFirstWithPointers) {
  json wrong = minimal();
  wrong["joints"][0]["type"] = "hinge";
  wrong["links"][0]["collision"] = {{"kind", "box"}, {"radius", -1}};
  const LoadedRobot loaded = load_robot_description(wrong);
  const auto found = pointers(loaded);
  EXPECT_NE(std::find(found.begin(), found.end(), "/joints/0/type"), found.end());
  EXPECT_NE(std::find(found.begin(), found.end(), "/links/0/collision/radius"), found.end());
}

TEST(RobotDescription, JointsNeedMotorsLimitsAndSizedShapes) {
  json wrong = minimal();
  wrong["joints"][0].erase("motor");
  wrong["joints"][0]["type"] = "prismatic";
  wrong["links"][1]["collision"] = {{"kind", "cylinder"}, {"radius", 0.1}};  // no length
  const auto found = pointers(load_robot_description(wrong));
  EXPECT_EQ(std::count(found.begin(), found.end(), "/joints/0"), 2) << "no motor, no limits";
  EXPECT_NE(std::find(found.begin(), found.end(), "/links/1/collision"), found.end());
  json mimic = minimal();
  mimic["links"].push_back({{"name", "twin"}});
  mimic["joints"].push_back({{"name", "follow"}, {"type", "continuous"}, {"parent", "base"}, {"child", "twin"},
                             {"mimic", {{"joint", "missing"}}}});
  EXPECT_EQ(pointers(load_robot_description(mimic)), std::vector<std::string>{"/joints/1/mimic/joint"});
}

}  // namespace
}  // namespace hrisim::robots
