// A person's solids and the pose an activity gives: they stand on the floor and reach the body's
// height, follow the joints, and blend between standing, walking and motion primitives.
#include "humans/body.hpp"
#include "humans/locomotion.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace hrisim::humans {
namespace {

const Capsule& part(const BodyCapsules& body, BodyPart which) { return body[static_cast<int>(which)]; }

double lowest(const BodyCapsules& body) {
  double z = 1e9;
  for (const Capsule& c : body) z = std::min({z, c.from.z() - c.radius, c.to.z() - c.radius});
  return z;
}

double highest(const BodyCapsules& body) {
  double z = -1e9;
  for (const Capsule& c : body) z = std::max({z, c.from.z() + c.radius, c.to.z() + c.radius});
  return z;
}

TEST(Body, AtRestTheSolidsStandOnTheFloorAndReachTheBodysHeight) {
  for (const BodyDimensions dims : {kAdultBody, kChildBody, kElderBody}) {
    const Skeleton skeleton(dims);
    const BodyCapsules body = body_capsules(skeleton, forward_kinematics(skeleton, SkeletonPose()));
    EXPECT_NEAR(lowest(body), 0.0, 0.01) << dims.height << " m: the soles on the floor";
    EXPECT_NEAR(highest(body), dims.height, 0.03) << "the top of the head";
    // As wide as the shoulders say, arms included.
    double widest = 0.0;
    for (const Capsule& c : body) widest = std::max({widest, std::abs(c.from.y()) + c.radius, std::abs(c.to.y()) + c.radius});
    EXPECT_NEAR(2 * widest, dims.width, 0.1 * dims.width);
  }
  EXPECT_EQ(body_part_name(BodyPart::l_forearm), "l_forearm");
}

TEST(Body, SolidsFollowTheJointsAndBonesKeepTheirLength) {
  const Skeleton adult(kAdultBody);
  const BodyCapsules rest = body_capsules(adult, forward_kinematics(adult, SkeletonPose()));
  Activity pointing;
  pointing.motion = builtin_motion("point_right");
  pointing.motion_time = 1.0;
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = Eigen::Vector3d(3, 4, 0);
  base.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();  // facing +y: her right is +x
  const BodyCapsules body = body_capsules(adult, forward_kinematics(adult, body_pose(pointing), base));
  EXPECT_GT(part(body, BodyPart::r_forearm).to.x(), 3.0 + 0.6) << "the right hand out to her right";
  EXPECT_NEAR(part(body, BodyPart::r_forearm).to.z(), part(body, BodyPart::r_upper_arm).from.z(), 0.05) << "at shoulder height";
  for (int p = 0; p < kBodyPartCount; ++p) {
    EXPECT_NEAR((body[p].to - body[p].from).norm(), (rest[p].to - rest[p].from).norm(), 1e-9) << body_part_name(static_cast<BodyPart>(p));
    EXPECT_EQ(body[p].radius, rest[p].radius);
  }
}

TEST(Body, ActivitiesBlendFromStandingToWalkingAndInAndOutOfMotions) {
  const MotionClip& walk = *builtin_motion("walk");
  const MotionClip& idle = *builtin_motion("idle");
  const MotionClip& wave = *builtin_motion("wave");
  const auto same = [](const SkeletonPose& a, const SkeletonPose& b) {
    for (int j = 0; j < kJointCount; ++j) {
      if (a.rotations[j].angularDistance(b.rotations[j]) > 1e-9) return false;
    }
    return (a.root - b.root).norm() < 1e-12;
  };
  Activity standing;
  standing.time = 1.3;
  EXPECT_TRUE(same(body_pose(standing), idle.sample(1.3)));
  Activity walking;
  walking.speed = kFullGaitSpeed;
  walking.gait_distance = 0.4;
  EXPECT_TRUE(same(body_pose(walking), walking_pose(walk, 0.4))) << "full gait from kFullGaitSpeed on";
  Activity slow = walking;
  slow.speed = kFullGaitSpeed / 2;
  EXPECT_TRUE(same(body_pose(slow), blend(idle.sample(0.0), walking_pose(walk, 0.4), 0.5)));
  // Turning on the spot steps; a turn twists the upper body, up to its limit.
  Activity turning;
  turning.turn_rate = 3.0;
  const SkeletonPose turned = body_pose(turning);
  EXPECT_NEAR(turned.rotations[static_cast<int>(Joint::vl5)].angularDistance(idle.sample(0.0).rotations[static_cast<int>(Joint::vl5)]),
              kMaxTurnTwist, 1e-9);
  // A motion blends in over kMotionBlendTime, and out once released.
  Activity waving;
  waving.motion = &wave;
  waving.motion_time = kMotionBlendTime / 2;
  EXPECT_TRUE(same(body_pose(waving), blend(idle.sample(0.0), wave.sample(kMotionBlendTime / 2), 0.5)));
  waving.motion_time = 1.0;
  EXPECT_TRUE(same(body_pose(waving), wave.sample(1.0)));
  waving.since_release = kMotionBlendTime / 4;
  EXPECT_TRUE(same(body_pose(waving), blend(idle.sample(0.0), wave.sample(1.0), 0.75)));
}

TEST(Body, AWalkersLimbsReachKLimbClearanceBeyondTheirDisc) {
  // The margin people keep from a robot they share a place with is what their stride needs: over a
  // whole gait cycle at full gait, or turning briskly on the spot, an adult's feet and hands stay
  // within the default disc plus kLimbClearance, and at full stride reach all but 2 cm of it.
  const Skeleton adult(kAdultBody);
  const double disc = CrowdAgent{}.radius;
  const auto reach = [&](const Activity& activity) {
    double farthest = 0.0;
    for (const Capsule& c : body_capsules(adult, forward_kinematics(adult, body_pose(activity)))) {
      farthest = std::max({farthest, c.from.head<2>().norm() + c.radius, c.to.head<2>().norm() + c.radius});
    }
    return farthest;
  };
  const MotionClip& walk = *builtin_motion("walk");
  double walking = 0.0, turning = 0.0;
  for (double distance = 0.0; distance < walk.speed() * walk.duration(); distance += 0.01) {
    Activity stride;
    stride.speed = 1.34;
    stride.gait_distance = distance;
    walking = std::max(walking, reach(stride));
    stride.speed = 0.0;
    stride.turn_rate = 3.0;
    turning = std::max(turning, reach(stride));
  }
  EXPECT_LE(walking, disc + kLimbClearance);
  EXPECT_GT(walking, disc + kLimbClearance - 0.02);
  EXPECT_LE(turning, disc + kLimbClearance);
  Activity standing;
  EXPECT_LE(reach(standing), disc) << "standing, the body is within its disc";
}

}  // namespace
}  // namespace hrisim::humans
