#include "world/occupancy_grid.hpp"

#include <gtest/gtest.h>

#include <limits>

#include "core/error.hpp"

namespace hrisim::world {
namespace {

TEST(OccupancyGrid, CellsAndCentres) {
  OccupancyGrid grid(0.5, {-1.0, -2.0}, 8, 4);
  EXPECT_EQ(grid.cell_of({-1.0, -2.0}), (CellIndex{0, 0}));
  EXPECT_EQ(grid.cell_of({0.74, -0.26}), (CellIndex{3, 3}));
  EXPECT_TRUE(grid.center_of({3, 3}).isApprox(Vec2(0.75, -0.25)));
  EXPECT_FALSE(grid.in_bounds(grid.cell_of({-1.01, 0.0})));
  EXPECT_TRUE(grid.blocked(Vec2(100.0, 0.0))) << "outside the map is blocked";
}

TEST(OccupancyGrid, PointsFarBeyondTheMapAreOutsideNotUndefined) {
  // Found by fuzzing scenario JSON: a goto pose at y = 1.1e82 was converted to an int cell index.
  const OccupancyGrid grid(0.5, {-1.0, -2.0}, 8, 4);
  for (const Vec2& far : {Vec2(20.0, 1.1e82), Vec2(-1e300, 0.0), Vec2(0.0, -std::numeric_limits<double>::infinity()),
                          Vec2(std::numeric_limits<double>::quiet_NaN(), 0.0)}) {
    EXPECT_FALSE(grid.in_bounds(grid.cell_of(far))) << far.transpose();
    EXPECT_TRUE(grid.blocked(far));
  }
}

TEST(OccupancyGrid, ImpossibleSizeIsRefused) {
  EXPECT_THROW(OccupancyGrid(0.0, {0, 0}, 10, 10), core::Error);
  EXPECT_THROW(OccupancyGrid(0.1, {0, 0}, 0, 10), core::Error);
}

TEST(OccupancyGrid, ThinWallIsNotLostBetweenCellCentres) {
  OccupancyGrid grid(0.1, {0, 0}, 50, 50);
  // A 1 cm thick wall at x = 2.02 — between the centres of columns 19 (1.95) and 20 (2.05).
  grid.fill_polygon({{2.015, 0.5}, {2.025, 0.5}, {2.025, 4.5}, {2.015, 4.5}});
  for (int y = 6; y < 44; ++y) EXPECT_TRUE(grid.blocked(CellIndex{20, y})) << y;
  EXPECT_FALSE(grid.blocked(CellIndex{18, 20}));
  EXPECT_FALSE(grid.blocked(CellIndex{22, 20}));
}

TEST(OccupancyGrid, PolygonInterior) {
  OccupancyGrid grid(0.1, {0, 0}, 40, 40);
  grid.fill_polygon({{1, 1}, {3, 1}, {3, 3}, {1, 3}});
  EXPECT_TRUE(grid.blocked(Vec2(2.0, 2.0)));
  EXPECT_FALSE(grid.blocked(Vec2(0.5, 0.5)));
  EXPECT_FALSE(grid.blocked(Vec2(3.5, 2.0)));
}

TEST(DistanceField, DistancesToTheNearestObstacle) {
  OccupancyGrid grid(0.1, {0, 0}, 60, 30);
  grid.fill_polygon({{0.0, 0.0}, {0.1, 0.0}, {0.1, 3.0}, {0.0, 3.0}});  // wall along x = 0..0.1
  const DistanceField field(grid);
  EXPECT_NEAR(field.distance(grid, {2.05, 1.55}), 2.0, 1e-5);
  EXPECT_NEAR(field.distance(grid, {0.05, 1.55}), 0.0, 1e-9);
  const auto nearest = field.nearest_obstacle(grid, {3.05, 1.55});
  ASSERT_TRUE(nearest);
  EXPECT_NEAR(nearest->x(), 0.05, 1e-9);
  EXPECT_NEAR(nearest->y(), 1.55, 1e-9);
}

TEST(DistanceField, MatchesBruteForce) {
  OccupancyGrid grid(0.1, {0, 0}, 40, 40);
  grid.fill_polygon({{1.0, 1.0}, {1.6, 1.2}, {1.2, 2.5}});
  grid.fill_polygon({{3.0, 0.2}, {3.3, 0.2}, {3.3, 3.8}, {3.0, 3.8}});
  const DistanceField field(grid);
  double worst = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    double best = 1e9;
    for (std::size_t j = 0; j < grid.size(); ++j) {
      if (grid.blocked(grid.cell_at(j))) {
        best = std::min(best, (grid.center_of(grid.cell_at(i)) - grid.center_of(grid.cell_at(j))).norm());
      }
    }
    worst = std::max(worst, std::abs(field.distance(i) - best));
  }
  EXPECT_LT(worst, 0.05) << "propagated distances stay within half a cell of the exact ones";
}

TEST(DistanceField, EmptyMapHasNoObstacle) {
  OccupancyGrid grid(0.1, {0, 0}, 10, 10);
  const DistanceField field(grid);
  EXPECT_FALSE(field.nearest_obstacle(grid, {0.5, 0.5}));
  EXPECT_GT(field.distance(grid, {0.5, 0.5}), 1e6);
}

}  // namespace
}  // namespace hrisim::world
