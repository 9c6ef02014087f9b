#include "world/path_planner.hpp"

#include <gtest/gtest.h>

namespace hrisim::world {
namespace {

// A 10 m × 6 m room with a wall across the middle that leaves a 1 m gap at the top.
struct Room {
  Room() : grid(0.05, {0, 0}, 200, 120) {
    grid.fill_polygon({{0, 0}, {10, 0}, {10, 0.1}, {0, 0.1}});
    grid.fill_polygon({{0, 5.9}, {10, 5.9}, {10, 6}, {0, 6}});
    grid.fill_polygon({{0, 0}, {0.1, 0}, {0.1, 6}, {0, 6}});
    grid.fill_polygon({{9.9, 0}, {10, 0}, {10, 6}, {9.9, 6}});
    grid.fill_polygon({{4.9, 0}, {5.1, 0}, {5.1, 4.9}, {4.9, 4.9}});
  }
  OccupancyGrid grid;
};

double length(const Vec2& start, const std::vector<Vec2>& path) {
  double total = 0.0;
  Vec2 previous = start;
  for (const Vec2& p : path) {
    total += (p - previous).norm();
    previous = p;
  }
  return total;
}

TEST(PathPlanner, GoesThroughTheGapWithClearance) {
  Room room;
  const DistanceField field(room.grid);
  const PathPlanner planner(room.grid, field);
  const Vec2 start(2.0, 1.0), goal(8.0, 1.0);
  const auto path = planner.plan(start, goal, 0.3);
  ASSERT_TRUE(path);
  EXPECT_TRUE(path->back().isApprox(goal));
  bool crossed_in_gap = false;
  Vec2 previous = start;
  for (const Vec2& p : *path) {
    EXPECT_TRUE(planner.line_of_sight(previous, p, 0.3)) << "smoothed legs stay clear of walls";
    if ((previous.x() < 5.0) != (p.x() < 5.0)) {
      const double t = (5.0 - previous.x()) / (p.x() - previous.x());
      crossed_in_gap = previous.y() + t * (p.y() - previous.y()) > 4.9 + 0.3;
    }
    previous = p;
  }
  EXPECT_TRUE(crossed_in_gap);
  EXPECT_LT(path->size(), 6u) << "smoothing removes the grid staircase";
  // The detour: up to the gap and back down, about 2 × √(3² + 4²) = 10 m, not the 6 m straight line.
  EXPECT_GT(length(start, *path), 9.0);
  EXPECT_LT(length(start, *path), 11.0);
}

TEST(PathPlanner, TooWideToPassHasNoPath) {
  Room room;
  const DistanceField field(room.grid);
  const PathPlanner planner(room.grid, field);
  EXPECT_FALSE(planner.plan({2.0, 1.0}, {8.0, 1.0}, 0.6)) << "a 1.2 m disc does not fit a 1 m gap";
  EXPECT_TRUE(planner.plan({2.0, 1.0}, {3.0, 3.0}, 0.6)) << "but moves within its half";
}

TEST(PathPlanner, TemporaryBlockedCellsCloseTheGap) {
  Room room;
  const DistanceField field(room.grid);
  const PathPlanner planner(room.grid, field);
  std::vector<std::size_t> door;
  for (double y = 4.9; y < 5.9; y += 0.05) door.push_back(room.grid.index(room.grid.cell_of({5.0, y + 0.01})));
  EXPECT_FALSE(planner.plan({2.0, 1.0}, {8.0, 1.0}, 0.3, door));
  EXPECT_TRUE(planner.plan({2.0, 1.0}, {8.0, 1.0}, 0.3)) << "the cache keeps the open-door field apart";
}

TEST(PathPlanner, StraightLineInTheOpen) {
  Room room;
  const DistanceField field(room.grid);
  const PathPlanner planner(room.grid, field);
  const auto path = planner.plan({1.0, 1.0}, {4.0, 4.0}, 0.3);
  ASSERT_TRUE(path);
  EXPECT_EQ(path->size(), 1u);
}

TEST(PathPlanner, OutsideTheMapHasNoPath) {
  Room room;
  const DistanceField field(room.grid);
  const PathPlanner planner(room.grid, field);
  EXPECT_FALSE(planner.plan({1.0, 1.0}, {40.0, 1.0}, 0.3));
}


// The wall ends at y = 4.9 and leaves a gap above it; a path from the left half to the right half
// turns at a corner above the wall's end.
TEST(PathPlanner, PushedOffTheLegWalksOnWhileTheWaypointIsInSight) {
  Room room;
  const DistanceField field(room.grid);
  const PathPlanner planner(room.grid, field);
  const Vec2 corner(5.0, 5.4), goal(8.0, 1.0);
  EXPECT_EQ(planner.rejoin({2.0, 3.0}, {1.0, 1.0}, corner, 0.3), Rejoin::walk_on);
  EXPECT_EQ(planner.rejoin({7.0, 4.0}, corner, goal, 0.3), Rejoin::walk_on) << "past the corner, goal in sight";
  EXPECT_EQ(planner.rejoin({1.5, 4.0}, corner, goal, 0.3), Rejoin::back_to_corner) << "pushed back behind the wall";
  EXPECT_EQ(planner.rejoin({1.5, 4.0}, {8.0, 5.4}, goal, 0.3), Rejoin::replan) << "neither end of the leg in sight";
}

TEST(PathPlanner, RejoinNeedsOnlyTheClearanceAskedFor) {
  Room room;
  const DistanceField field(room.grid);
  const PathPlanner planner(room.grid, field);
  // Along the wall's right face, 0.2 m from it.
  const Vec2 position(5.3, 2.0), waypoint(5.3, 5.4);
  EXPECT_EQ(planner.rejoin(position, position, waypoint, 0.3), Rejoin::replan);
  EXPECT_EQ(planner.rejoin(position, position, waypoint, 0.15), Rejoin::walk_on);
}

/// Plans from `start` to `goal` with `history` until its requests descend the goal's field.
std::optional<std::vector<Vec2>> plan_until_field(const PathPlanner& planner, PlanningHistory& history,
                                                  const Vec2& start, const Vec2& goal) {
  std::optional<std::vector<Vec2>> path;
  for (int i = 0; i < 100000 && history.field_descents() == 0; ++i) path = planner.plan(start, goal, 0.3, {}, history);
  return path;
}

// Early requests for a goal are A* searches, later ones descend its field; both are shortest.
TEST(PathPlanner, SearchAndFieldAgree) {
  Room room;
  const DistanceField field(room.grid);
  const PathPlanner planner(room.grid, field);
  PlanningHistory history;
  const Vec2 start(2.0, 1.0), goal(8.0, 1.5);
  const auto searched = planner.plan(start, goal, 0.3, {}, history);
  EXPECT_EQ(history.field_descents(), 0u) << "a first request is a search";
  const auto descended = plan_until_field(planner, history, start, goal);
  ASSERT_EQ(history.field_descents(), 1u) << "searching again and again makes the field pay";
  ASSERT_TRUE(searched);
  ASSERT_TRUE(descended);
  EXPECT_NEAR(length(start, *searched), length(start, *descended), 0.3) << "equally short up to the smoothing of grid corners";
  const auto from_elsewhere = planner.plan({3.0, 3.0}, goal, 0.3, {}, history);
  ASSERT_TRUE(from_elsewhere);
  EXPECT_TRUE(from_elsewhere->back().isApprox(goal));
  EXPECT_EQ(history.field_descents(), 2u) << "the same goal from elsewhere uses the field too";
}

// A field computed for one caller must not change another caller's paths (sessions share planners).
TEST(PathPlanner, PathsDependOnlyOnTheCallersOwnHistory) {
  Room room;
  const DistanceField field(room.grid);
  const PathPlanner shared(room.grid, field), untouched(room.grid, field);
  PlanningHistory busy, fresh;
  const Vec2 goal(8.0, 1.5);
  plan_until_field(shared, busy, {2.0, 1.0}, goal);
  ASSERT_EQ(busy.field_descents(), 1u);
  for (const Vec2& start : {Vec2(1.0, 1.0), Vec2(2.5, 4.0), Vec2(3.7, 2.2), Vec2(1.2, 5.2)}) {
    const auto path = shared.plan(start, goal, 0.3, {}, fresh);
    const auto alone = untouched.plan(start, goal, 0.3);
    ASSERT_TRUE(path);
    ASSERT_TRUE(alone);
    EXPECT_EQ(*path, *alone) << "from " << start.transpose();
  }
  EXPECT_EQ(fresh.field_descents(), 0u);
}

}  // namespace
}  // namespace hrisim::world
