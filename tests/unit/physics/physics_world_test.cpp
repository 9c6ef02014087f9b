#include "physics/physics_world.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace hrisim::physics {
namespace {

constexpr double kDt = 1.0 / 60.0;

robots::Shape box(double x, double y, double z) {
  robots::Shape shape;
  shape.kind = robots::Shape::Kind::box;
  shape.size = {x, y, z};
  return shape;
}

robots::Shape cylinder(double radius, double length) {
  robots::Shape shape;
  shape.kind = robots::Shape::Kind::cylinder;
  shape.radius = radius;
  shape.length = length;
  return shape;
}

Eigen::Isometry3d at(double x, double y, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translate(Eigen::Vector3d(x, y, z));
  return pose;
}

TEST(PhysicsWorld, DroppedBoxComesToRestOnTheFloor) {
  PhysicsWorld world(kDt);
  world.add_floor_and_walls({}, 2.0);
  const int crate = world.add_dynamic(box(0.4, 0.4, 0.2), 2.0, at(0, 0, 0.3), {BodyOwner::Kind::object, 0, "crate"});
  for (int i = 0; i < 180; ++i) world.step();
  EXPECT_NEAR(world.pose(crate).translation().z(), 0.1, 0.01);
  EXPECT_NEAR(world.pose(crate).translation().x(), 0.0, 1e-6);
  const auto touching = world.touching();
  EXPECT_NE(std::find(touching.begin(), touching.end(), std::pair{0, crate}), touching.end()) << "resting on the floor";
}

TEST(PhysicsWorld, CupRestsOnATableTopAndAWallStopsABox) {
  PhysicsWorld world(kDt);
  const std::vector<world::Segment> wall{{{2.0, -1.0}, {2.0, 1.0}}};
  world.add_floor_and_walls(wall, 2.0);
  world.add_static_prism({{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}}, 0.75, {BodyOwner::Kind::map, -1, "table"});
  const int cup = world.add_dynamic(cylinder(0.04, 0.1), 0.2, at(0, 0, 0.85), {BodyOwner::Kind::object, 0, "cup"});
  // A kinematic pusher sweeps a box towards the wall.
  const int crate = world.add_dynamic(box(0.3, 0.3, 0.3), 1.0, at(1.0, 0, 0.15), {BodyOwner::Kind::object, 1, "crate"});
  const int pusher = world.add_kinematic(box(0.1, 0.6, 0.4), at(0.7, 0, 0.2), {BodyOwner::Kind::robot, 0, "bumper"});
  for (int i = 0; i < 240; ++i) {
    world.set_kinematic_pose(pusher, at(0.7 + std::min(i, 90) * 0.01, 0, 0.2));
    world.step();
  }
  EXPECT_NEAR(world.pose(cup).translation().z(), 0.75 + 0.05, 0.01) << "on the table top";
  const double crate_x = world.pose(crate).translation().x();
  EXPECT_GT(crate_x, 1.5) << "pushed";
  EXPECT_LT(crate_x, 2.0 - 0.15 + 0.02) << "stopped by the wall";
}

TEST(PhysicsWorld, HeldBodyFollowsItsHolderAndFallsWhenReleased) {
  PhysicsWorld world(kDt);
  world.add_floor_and_walls({}, 2.0);
  const int hand = world.add_kinematic(box(0.05, 0.05, 0.05), at(0, 0, 0.5), {BodyOwner::Kind::robot, 0, "hand"});
  const int cup = world.add_dynamic(cylinder(0.04, 0.1), 0.2, at(0, 0.1, 0.5), {BodyOwner::Kind::object, 0, "cup"});
  world.attach(cup, hand);
  EXPECT_EQ(world.holder(cup), hand);
  world.step();
  const Wrench at_rest = world.hold_load(cup);
  EXPECT_NEAR(at_rest.force.z(), 0.2 * kGravity, 0.05) << "the joint carries the cup's weight";
  EXPECT_NEAR(at_rest.force.head<2>().norm(), 0.0, 0.05);
  EXPECT_NEAR(at_rest.torque.norm(), 0.0, 0.01) << "about the cup's own centre";
  for (int i = 0; i < 90; ++i) {
    world.set_kinematic_pose(hand, at(std::min(i, 59) * 0.01, 0, 0.5 + std::min(i, 59) * 0.005));
    world.step();
  }
  // Held by a joint, the cup stays dynamic: it follows, and settles where it is held when the hand stops.
  EXPECT_NEAR(world.pose(cup).translation().x(), 0.59, 2e-3);
  EXPECT_NEAR(world.pose(cup).translation().y(), 0.1, 2e-3);
  EXPECT_NEAR(world.pose(cup).translation().z(), 0.5 + 59 * 0.005, 2e-3);
  world.detach(cup);
  EXPECT_EQ(world.hold_load(cup).force.norm(), 0.0);
  for (int i = 0; i < 120; ++i) world.step();
  EXPECT_EQ(world.holder(cup), -1);
  EXPECT_LT(world.pose(cup).translation().z(), 0.06) << "fell to the floor (standing or lying)";
  EXPECT_GT(world.pose(cup).translation().z(), 0.02);
}

TEST(PhysicsWorld, SameOperationsSameBits) {
  auto run = [] {
    PhysicsWorld world(kDt);
    world.add_floor_and_walls({}, 2.0);
    std::vector<int> crates;
    for (int i = 0; i < 5; ++i) {
      crates.push_back(world.add_dynamic(box(0.2, 0.2, 0.2), 1.0, at(0.05 * i, 0, 0.3 + 0.25 * i), {BodyOwner::Kind::object, i, "crate"}));
    }
    for (int i = 0; i < 200; ++i) world.step();
    std::vector<double> state;
    for (const int crate : crates) {
      const Eigen::Isometry3d pose = world.pose(crate);
      state.insert(state.end(), pose.data(), pose.data() + 16);
    }
    return state;
  };
  EXPECT_EQ(run(), run());
}

}  // namespace
}  // namespace hrisim::physics
