#include "world/outline.hpp"

#include <gtest/gtest.h>

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

TEST(Outline, PolygonEdgesCloseTheLoop) {
  std::vector<Segment> segments;
  append_edges({{0, 0}, {1, 0}, {1, 1}}, segments);
  ASSERT_EQ(segments.size(), 3u);
  EXPECT_EQ(segments[2].b, Vec2(0, 0));
}

}  // namespace
}  // namespace hrisim::world
