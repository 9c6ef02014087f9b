#pragma once
// Global paths on the occupancy grid, inflated by the agent's radius: 8-connected shortest paths
// (octile costs), smoothed by line of sight. Goals are searched with A* (octile heuristic); a goal
// asked for often gets its whole cost-to-go field computed (Dijkstra from the goal) and cached, so
// every later agent heading there descends it without searching.
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <tuple>
#include <vector>

#include "world/occupancy_grid.hpp"

namespace hrisim::world {

/// Goals whose cost-to-go fields are kept per planner (least recently used dropped first).
inline constexpr std::size_t kPlannerCacheSize = 64;
/// A goal gets its own cost-to-go field from this many requests on (a place many agents head to);
/// before that each request is an A* search, which is far cheaper for a one-off goal.
inline constexpr int kFieldAfterRequests = 8;

class PathPlanner {
 public:
  /// The grid and field must outlive the planner.
  PathPlanner(const OccupancyGrid& grid, const DistanceField& field);

  /// Waypoints from start (exclusive) to goal (inclusive, exact), or nothing when the goal cannot be
  /// reached by a disc of `radius`. `blocked_cells` are closed doors and other temporary obstacles
  /// (indices into the grid), part of the cache key.
  std::optional<std::vector<Vec2>> plan(const Vec2& start, const Vec2& goal, double radius,
                                        const std::vector<std::size_t>& blocked_cells = {}) const;

  /// True when a disc of `radius` can move in a straight line from a to b.
  bool line_of_sight(const Vec2& a, const Vec2& b, double radius,
                     const std::vector<std::size_t>& blocked_cells = {}) const;

  /// Whether a disc of `radius` centred in the cell fits.
  bool traversable(std::size_t cell, double radius, const std::vector<std::size_t>& blocked_cells = {}) const;

 private:
  using CacheKey = std::tuple<std::size_t, int, std::vector<std::size_t>>;  // goal cell, radius in mm, blocked
  /// The cached field of a goal, computed once the goal is asked for often enough; null before that.
  std::shared_ptr<const std::vector<float>> cost_to_go(std::size_t goal_cell, double radius,
                                                       const std::vector<std::size_t>& blocked_cells) const;
  std::optional<std::vector<std::size_t>> a_star(std::size_t start_cell, std::size_t goal_cell, double radius,
                                                 const std::vector<std::size_t>& blocked_cells) const;
  bool diagonal_allowed(CellIndex from, int dx, int dy, double radius, const std::vector<std::size_t>& blocked) const;
  std::optional<std::size_t> nearest_traversable(std::size_t cell, double radius,
                                                 const std::vector<std::size_t>& blocked_cells) const;

  const OccupancyGrid& grid_;
  const DistanceField& field_;
  mutable std::mutex mutex_;
  mutable std::list<CacheKey> recency_;
  mutable std::map<CacheKey, std::shared_ptr<const std::vector<float>>> cache_;
  mutable std::map<CacheKey, int> requests_;  ///< goals asked for once, not yet worth a field
};

}  // namespace hrisim::world
