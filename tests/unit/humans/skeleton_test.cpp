// The H-Anim skeleton's rest pose and kinematics, and motion primitives: interpolation, looping,
// blending, the shipped files, and bad files refused with their place.
#include "humans/skeleton.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "humans/motion.hpp"

namespace hrisim::humans {
namespace {

Eigen::Vector3d at(const std::array<Eigen::Isometry3d, kJointCount>& frames, Joint joint) {
  return frames[static_cast<int>(joint)].translation();
}

TEST(Skeleton, NamesAndHierarchyFollowHAnim) {
  EXPECT_EQ(joint_name(Joint::l_shoulder), "l_shoulder");
  EXPECT_EQ(joint_by_name("skullbase"), Joint::skullbase);
  EXPECT_FALSE(joint_by_name("l_toe"));
  EXPECT_EQ(parent(Joint::l_wrist), Joint::l_elbow);
  EXPECT_EQ(parent(Joint::vc7), Joint::vl5);
  for (int j = 1; j < kJointCount; ++j) EXPECT_LT(static_cast<int>(parent(static_cast<Joint>(j))), j) << "parents come first";
  EXPECT_EQ(body_dimensions("child")->height, 1.20);
  EXPECT_FALSE(body_dimensions("robot"));
}

TEST(Skeleton, RestPoseStandsUprightWithAnthropometricHeights) {
  const Skeleton adult(kAdultBody);
  const auto frames = forward_kinematics(adult, SkeletonPose());
  EXPECT_NEAR(at(frames, Joint::humanoid_root).z(), 0.530 * 1.75, 1e-12);
  EXPECT_NEAR(at(frames, Joint::l_knee).z(), 0.285 * 1.75, 1e-12);
  EXPECT_NEAR(at(frames, Joint::l_ankle).z(), 0.039 * 1.75, 1e-12);
  EXPECT_NEAR(at(frames, Joint::r_shoulder).z(), 0.818 * 1.75, 1e-12);
  EXPECT_NEAR(at(frames, Joint::l_wrist).z(), 0.485 * 1.75, 1e-12);
  EXPECT_NEAR(at(frames, Joint::l_shoulder).y() - at(frames, Joint::r_shoulder).y(), 0.8 * 0.45, 1e-12);
  // Left and right mirror each other.
  for (const auto& [left, right] : {std::pair{Joint::l_hip, Joint::r_hip}, {Joint::l_ankle, Joint::r_ankle}, {Joint::l_wrist, Joint::r_wrist}}) {
    EXPECT_NEAR(at(frames, left).y(), -at(frames, right).y(), 1e-12);
    EXPECT_NEAR(at(frames, left).z(), at(frames, right).z(), 1e-12);
  }
  const auto child = forward_kinematics(Skeleton(kChildBody), SkeletonPose());
  EXPECT_LT(at(child, Joint::skullbase).z(), at(frames, Joint::skullbase).z());
}

TEST(Skeleton, RotationsMoveWhatHangsBelowAndKeepBoneLengths) {
  const Skeleton adult(kAdultBody);
  SkeletonPose pose;
  pose.rotations[static_cast<int>(Joint::l_shoulder)] = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX());
  pose.rotations[static_cast<int>(Joint::r_knee)] = Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitY());
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translate(Eigen::Vector3d(2, 3, 0)).rotate(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()));
  const auto rest = forward_kinematics(adult, SkeletonPose(), base), posed = forward_kinematics(adult, pose, base);
  for (int j = 1; j < kJointCount; ++j) {
    const auto joint = static_cast<Joint>(j);
    const double rest_length = (at(rest, joint) - at(rest, parent(joint))).norm();
    EXPECT_NEAR((at(posed, joint) - at(posed, parent(joint))).norm(), rest_length, 1e-12) << joint_name(joint);
  }
  // The left arm points to the person's left, level with the shoulder; the right one did not move.
  const Eigen::Vector3d arm = at(posed, Joint::l_wrist) - at(posed, Joint::l_shoulder);
  const Eigen::Vector3d left = base.linear() * Eigen::Vector3d::UnitY();
  EXPECT_NEAR(arm.normalized().dot(left), 1.0, 1e-12);
  EXPECT_TRUE(at(posed, Joint::r_wrist).isApprox(at(rest, Joint::r_wrist), 1e-12));
  EXPECT_FALSE(at(posed, Joint::r_ankle).isApprox(at(rest, Joint::r_ankle), 1e-6)) << "below the bent knee";
}

TEST(Motion, KeyframesInterpolateAndLoop) {
  const MotionClip clip = MotionClip::parse(nlohmann::json::parse(R"({
    "name": "test", "duration": 2.0, "loop": true,
    "keyframes": [{"time": 0, "root": [0, 0, 0]}, {"time": 1, "root": [1, 0, 0], "joints": {"l_elbow": [1.0, 0, 0]}},
                  {"time": 2, "root": [0, 0, 0]}]})"));
  EXPECT_EQ(clip.sample(1.0).root, Eigen::Vector3d(1, 0, 0));
  const SkeletonPose half = clip.sample(0.5);
  EXPECT_NEAR(half.root.x(), 0.5, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(half.rotations[static_cast<int>(Joint::l_elbow)]).angle(), 0.5, 1e-12) << "slerp halfway";
  EXPECT_NEAR(clip.sample(2.5).root.x(), 0.5, 1e-12) << "a looping clip wraps";
  const MotionClip once = MotionClip::parse(nlohmann::json::parse(R"({"name": "once", "duration": 1.0,
    "keyframes": [{"time": 0}, {"time": 1, "root": [0, 1, 0]}]})"));
  EXPECT_EQ(once.sample(5.0).root, Eigen::Vector3d(0, 1, 0)) << "a clip that does not loop holds its last pose";
  const SkeletonPose mixed = blend(clip.sample(1.0), once.sample(1.0), 0.25);
  EXPECT_TRUE(mixed.root.isApprox(Eigen::Vector3d(0.75, 0.25, 0), 1e-12));
}

TEST(Motion, BadFilesAreRefusedWithTheirPlace) {
  const std::vector<std::pair<const char*, const char*>> cases{
      {R"({"duration": 1, "keyframes": [{"time": 0}]})", "/name"},
      {R"({"name": "x", "duration": 0, "keyframes": [{"time": 0}]})", "/duration"},
      {R"({"name": "x", "duration": 1, "keyframes": []})", "/keyframes"},
      {R"({"name": "x", "duration": 1, "keyframes": [{"time": 0.2}]})", "/keyframes/0/time"},
      {R"({"name": "x", "duration": 1, "keyframes": [{"time": 0}, {"time": 0}]})", "/keyframes/1/time"},
      {R"({"name": "x", "duration": 1, "keyframes": [{"time": 0}, {"time": 0.5}]})", "/keyframes/1/time"},
      {R"({"name": "x", "duration": 1, "keyframes": [{"time": 0, "joints": {"l_toe": [0, 0, 1]}}]})", "/keyframes/0/joints/l_toe"},
      {R"({"name": "x", "duration": 1, "keyframes": [{"time": 0, "root": [0, 1]}]})", "/keyframes/0/root"},
      {R"({"name": "x", "duration": 1, "speed": -1, "keyframes": [{"time": 0}]})", "/speed"},
      {R"({"name": "x", "duration": 1, "tempo": 2, "keyframes": [{"time": 0}]})", "/tempo"},
  };
  for (const auto& [text, pointer] : cases) {
    try {
      MotionClip::parse(nlohmann::json::parse(text));
      ADD_FAILURE() << "accepted " << text;
    } catch (const core::Error& e) {
      EXPECT_EQ(e.details()["pointer"], pointer) << text << ": " << e.what();
    }
  }
}

TEST(Motion, TheShippedPrimitivesLoadAndPointingLeftMirrorsPointingRight) {
  const auto names = builtin_motion_names();
  for (const char* expected : {"idle", "walk", "step", "turn_in_place", "sit_down", "stand_up", "wave", "point_left", "point_right",
                               "press_button", "fall", "lie", "get_up"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  }
  for (const std::string& name : names) ASSERT_TRUE(builtin_motion(name)) << name;
  EXPECT_FALSE(builtin_motion("fly"));
  const Skeleton adult(kAdultBody);
  const auto left = forward_kinematics(adult, builtin_motion("point_left")->sample(1.0));
  const auto right = forward_kinematics(adult, builtin_motion("point_right")->sample(1.0));
  EXPECT_NEAR(at(left, Joint::l_wrist).y(), -at(right, Joint::r_wrist).y(), 1e-4);
  EXPECT_NEAR(at(left, Joint::l_wrist).z(), at(left, Joint::l_shoulder).z(), 1e-4) << "the arm is level";
  EXPECT_GT(at(left, Joint::l_wrist).y(), at(left, Joint::l_shoulder).y() + 0.4);
  const auto waving = forward_kinematics(adult, builtin_motion("wave")->sample(1.0));
  EXPECT_GT(at(waving, Joint::r_wrist).z(), at(waving, Joint::skullbase).z()) << "the waving hand is above the head";
}

TEST(Motion, SittingLyingPressingAndTurningEndWhereTheyShould) {
  const Skeleton adult(kAdultBody);
  const auto end_of = [&](const char* name) {
    const MotionClip& clip = *builtin_motion(name);
    return forward_kinematics(adult, clip.sample(clip.duration()));
  };
  const auto rest = forward_kinematics(adult, SkeletonPose());
  // Seated on a 0.45 m seat: hips 6 cm above it, thighs level, feet on the floor.
  const auto seated = end_of("sit_down");
  EXPECT_NEAR(at(seated, Joint::l_hip).z(), 0.51, 0.01);
  EXPECT_NEAR(at(seated, Joint::l_knee).z(), at(seated, Joint::l_hip).z(), 1e-6);
  EXPECT_NEAR(at(seated, Joint::r_ankle).z(), at(rest, Joint::r_ankle).z(), 0.02);
  const MotionClip& stand_up = *builtin_motion("stand_up");
  EXPECT_TRUE(at(forward_kinematics(adult, stand_up.sample(0.0)), Joint::skullbase).isApprox(at(seated, Joint::skullbase), 1e-9));
  EXPECT_TRUE(at(end_of("stand_up"), Joint::skullbase).isApprox(at(rest, Joint::skullbase), 1e-12));
  // Lying after a fall: the whole body within 35 cm of the floor, and get_up ends standing.
  for (const char* name : {"fall", "lie"}) {
    for (const auto& frame : end_of(name)) EXPECT_LT(frame.translation().z(), 0.35) << name;
  }
  EXPECT_TRUE(at(end_of("get_up"), Joint::skullbase).isApprox(at(rest, Joint::skullbase), 1e-12));
  // Pressing a button: the right hand 0.5 m ahead of the body at shoulder height.
  const auto pressing = forward_kinematics(adult, builtin_motion("press_button")->sample(0.8));
  EXPECT_GT(at(pressing, Joint::r_wrist).x(), 0.5);
  EXPECT_NEAR(at(pressing, Joint::r_wrist).z(), at(pressing, Joint::r_shoulder).z(), 0.05);
  // A quarter turn to the left: the shoulders' line, left minus right, now points backwards (−x).
  const auto turned = end_of("turn_in_place");
  const Eigen::Vector3d across = at(turned, Joint::l_shoulder) - at(turned, Joint::r_shoulder);
  EXPECT_NEAR(across.normalized().x(), -1.0, 1e-9);
  // One step advances the body by half a stride.
  EXPECT_NEAR(at(end_of("step"), Joint::humanoid_root).x(), 0.7, 0.01);
}

TEST(Motion, WalkingAtItsSpeedTheStanceFootDoesNotSlide) {
  // The walker moves humanoid_root forward at the clip's speed; a foot on the ground must then stay
  // where it is. The clip puts the left foot down for the first half of each stride and the right
  // foot for the second; over two strides at 240 Hz, each stance's foot moves less than the bound
  // and stays at ankle height.
  constexpr double kSlideBound = 0.02;  // m
  const MotionClip& walk = *builtin_motion("walk");
  ASSERT_GT(walk.speed(), 0.0);
  const Skeleton adult(kAdultBody);
  const double ground = at(forward_kinematics(adult, SkeletonPose()), Joint::l_ankle).z();
  const double period = walk.duration();
  for (const auto& [foot, stance_start] : {std::pair{Joint::l_ankle, 0.0}, std::pair{Joint::r_ankle, 0.5}}) {
    for (int stride = 0; stride < 2; ++stride) {
      const double begin = (stride + stance_start) * period;
      Eigen::Vector3d first = Eigen::Vector3d::Zero();
      double worst = 0.0;
      for (int i = 0; i <= 60; ++i) {
        const double t = begin + 0.5 * period * i / 60;
        Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
        base.translation().x() = walk.speed() * t;
        const Eigen::Vector3d position = at(forward_kinematics(adult, walk.sample(t), base), foot);
        if (i == 0) first = position;
        worst = std::max(worst, (position - first).norm());
        EXPECT_NEAR(position.z(), ground, 0.005) << joint_name(foot) << " at " << t << " s";
      }
      EXPECT_LT(worst, kSlideBound) << joint_name(foot) << ", stride " << stride;
    }
  }
}

TEST(Motion, TheGaitFollowsTheDistanceSoFeetDoNotSlideAtAnySpeed) {
  // The pose depends on the distance walked only, never on time, so whatever the speed: while the
  // body advances by a distance, each planted foot moves less than 2 cm. Sampled off the keyframes'
  // grid (a third of a millimetre steps) over a stance each.
  const MotionClip& walk = *builtin_motion("walk");
  const Skeleton adult(kAdultBody);
  const double stride = walk.speed() * walk.duration();
  for (const auto& [foot, stance_start] : {std::pair{Joint::l_ankle, 0.0}, std::pair{Joint::r_ankle, 0.5}}) {
    Eigen::Vector3d first = Eigen::Vector3d::Zero();
    double worst = 0.0;
    for (int i = 0; i <= 2100; ++i) {
      const double distance = (stance_start + 0.5 * i / 2100) * stride;
      Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
      base.translation().x() = distance;
      const Eigen::Vector3d position = at(forward_kinematics(adult, walking_pose(walk, distance), base), foot);
      if (i == 0) first = position;
      worst = std::max(worst, (position - first).norm());
    }
    EXPECT_LT(worst, 0.02) << joint_name(foot);
  }
  EXPECT_THROW(walking_pose(*builtin_motion("wave"), 1.0), core::Error) << "not a clip walked in place";
}

}  // namespace
}  // namespace hrisim::humans
