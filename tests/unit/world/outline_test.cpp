#include "world/outline.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace hrisim::world {
namespace {

double total_length(const std::vector<Segment>& segments) {
  double length = 0.0;
  for (const Segment& segment : segments) length += (segment.b - segment.a).norm();
  return length;
}

TEST(Outline, OneCellIsASquare) {
  OccupancyGrid grid(0.5, {1.0, 2.0}, 4, 4);
  grid.set({1, 2}, Cell::occupied);
  const auto segments = occupied_outline(grid);
  ASSERT_EQ(segments.size(), 4u);
  EXPECT_DOUBLE_EQ(total_length(segments), 2.0);
  for (const Segment& segment : segments) {
    for (const Vec2& end : {segment.a, segment.b}) {
      EXPECT_TRUE(end.x() == 1.5 || end.x() == 2.0) << end.transpose();
      EXPECT_TRUE(end.y() == 3.0 || end.y() == 3.5) << end.transpose();
    }
  }
}

TEST(Outline, RunsAreMergedAndUnknownIsOpen) {
  OccupancyGrid grid(1.0, {0.0, 0.0}, 5, 3);
  for (int x = 0; x < 5; ++x) grid.set({x, 1}, Cell::occupied);  // a wall across the map
  grid.set({2, 0}, Cell::unknown);
  const auto segments = occupied_outline(grid);
  // Top and bottom edges are one run each (unknown below counts as open), plus the two ends.
  EXPECT_EQ(segments.size(), 4u);
  EXPECT_DOUBLE_EQ(total_length(segments), 12.0);
}

TEST(Outline, FreeSpaceIsOnTheLeftOfEveryEdge) {
  OccupancyGrid grid(0.5, {-1.0, -1.0}, 8, 8);
  for (const CellIndex c : {CellIndex{2, 2}, CellIndex{3, 2}, CellIndex{3, 3}, CellIndex{5, 6}}) grid.set(c, Cell::occupied);
  const auto segments = occupied_outline(grid);
  EXPECT_DOUBLE_EQ(total_length(segments), 8 * 0.5 + 4 * 0.5);  // an L of three cells and a lone cell
  for (const Segment& segment : segments) {
    ASSERT_TRUE(segment.one_sided);
    const Vec2 middle = 0.5 * (segment.a + segment.b), left = core::left_normal((segment.b - segment.a).normalized()) * 0.01;
    EXPECT_FALSE(grid.blocked(middle + left)) << middle.transpose();
    EXPECT_TRUE(grid.blocked(middle - left)) << middle.transpose();
  }
}

TEST(Outline, PolygonEdgesCloseTheLoopWithTheOutsideOnTheLeft) {
  for (const bool counter_clockwise : {true, false}) {
    std::vector<Vec2> triangle{{0, 0}, {1, 0}, {1, 1}};
    if (!counter_clockwise) std::reverse(triangle.begin(), triangle.end());
    std::vector<Segment> segments;
    append_edges(triangle, segments);
    ASSERT_EQ(segments.size(), 3u);
    for (std::size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(std::count_if(segments.begin(), segments.end(), [&](const Segment& next) { return next.a == segments[i].b; }), 1)
          << "a closed loop";
      const Vec2 middle = 0.5 * (segments[i].a + segments[i].b);
      EXPECT_FALSE(contains(triangle, middle + 0.01 * core::left_normal(segments[i].b - segments[i].a)));
    }
  }
}

}  // namespace
}  // namespace hrisim::world
