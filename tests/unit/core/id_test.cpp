#include "core/id.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/math.hpp"

namespace hrisim::core {
namespace {

struct HumanTag {};
using Humans = EntityTable<HumanTag, std::string>;

TEST(EntityTable, StaleIdFailsLoudly) {
  Humans humans;
  const auto alice = humans.add("alice");
  humans.remove(alice);
  const auto bob = humans.add("bob");  // reuses alice's slot
  EXPECT_EQ(bob.index, alice.index);
  EXPECT_NE(bob.generation, alice.generation);
  EXPECT_FALSE(humans.contains(alice));
  EXPECT_THROW(humans.at(alice), Error);
  EXPECT_THROW(humans.remove(alice), Error);
  EXPECT_EQ(humans.at(bob), "bob");
  EXPECT_THROW(humans.at(Humans::Key{}), Error);
}

TEST(EntityTable, IteratesInCreationOrderEvenWhenSlotsAreReused) {
  Humans humans;
  const auto a = humans.add("a");
  humans.add("b");
  humans.add("c");
  humans.remove(a);
  humans.add("d");  // takes slot 0, but was created last
  std::vector<std::string> order;
  humans.for_each([&](Humans::Key, const std::string& name) { order.push_back(name); });
  EXPECT_EQ(order, (std::vector<std::string>{"b", "c", "d"}));
  EXPECT_EQ(humans.size(), 3u);
  EXPECT_EQ(humans.ids().back().index, 0u);
}

TEST(Math, WrapAngleIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(wrap_angle(0.0), 0.0);
  EXPECT_DOUBLE_EQ(wrap_angle(std::numbers::pi), std::numbers::pi);
  EXPECT_DOUBLE_EQ(wrap_angle(-std::numbers::pi), std::numbers::pi);
  EXPECT_NEAR(wrap_angle(3 * std::numbers::pi / 2), -std::numbers::pi / 2, 1e-12);
  EXPECT_NEAR(wrap_angle(-7.0), -7.0 + 2 * std::numbers::pi, 1e-12);
}

TEST(Math, ComposeAppliesOffsetInTheBaseFrame) {
  const Pose2 base{1.0, 2.0, std::numbers::pi / 2};
  const Pose2 result = compose(base, {1.0, 0.0, 0.0});  // one metre ahead of a robot facing +y
  EXPECT_NEAR(result.x, 1.0, 1e-12);
  EXPECT_NEAR(result.y, 3.0, 1e-12);
  EXPECT_NEAR(result.theta, std::numbers::pi / 2, 1e-12);
}

TEST(Math, ClosestPointOnSegment) {
  EXPECT_TRUE(closest_point_on_segment({0.5, 1.0}, {0, 0}, {1, 0}).isApprox(Vec2(0.5, 0.0)));
  EXPECT_TRUE(closest_point_on_segment({-1.0, 1.0}, {0, 0}, {1, 0}).isApprox(Vec2(0.0, 0.0)));
  EXPECT_TRUE(closest_point_on_segment({3.0, 3.0}, {1, 1}, {1, 1}).isApprox(Vec2(1.0, 1.0)));
}

}  // namespace
}  // namespace hrisim::core
