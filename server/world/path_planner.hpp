#pragma once
// Global paths on the occupancy grid, inflated by the agent's radius: 8-connected shortest paths
// (octile costs), smoothed by line of sight. A goal in plain sight is reached in a straight line.
// Otherwise goals are searched with A* (octile heuristic) until the searches towards one goal have cost
// as much as its whole cost-to-go field (Dijkstra from the goal); from then on the field is used, and
// every later agent heading there descends it without searching (ski rental: never more than twice
// the work of the better choice made in hindsight).
//
// Which of the two a request uses is decided by the caller's own PlanningHistory, never by what other
// callers did: both give shortest paths but may break ties differently, and a session's trajectory
// must not depend on other sessions sharing the planner. The fields themselves are a pure function of
// the goal and are shared between callers (a memo: it changes speed, not results).
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <tuple>
#include <vector>

#include "core/state_hash.hpp"
#include "world/occupancy_grid.hpp"

namespace hrisim::world {

/// Goals whose cost-to-go fields are kept per planner (least recently used dropped first).
inline constexpr std::size_t kPlannerCacheSize = 64;
/// Goals a PlanningHistory remembers before it starts over (bounded memory of one-off goals).
inline constexpr std::size_t kPlanningHistoryGoals = 65536;

/// Goal cell, radius in mm, sorted blocked cells: what a path and a field depend on.
using PlanKey = std::tuple<std::size_t, int, std::vector<std::size_t>>;

/// The search work one caller (a session) has spent per goal; owned by the caller.
class PlanningHistory {
 public:
  void clear() {
    searched_cells_.clear();
    digest_ = 0;
  }
  /// Requests answered from a goal's field rather than by a search.
  std::size_t field_descents() const { return field_descents_; }
  /// Adds everything it holds to a state hash, in constant time: a digest of the goals is kept as they
  /// change, since the hash is taken every tick and the history grows with the session.
  void hash(core::StateHasher& hasher) const;

 private:
  friend class PathPlanner;
  /// A goal's entry, created with nothing searched if new.
  std::map<PlanKey, std::size_t>::iterator entry(const PlanKey& key);
  /// Sets how many cells were searched for an entry's goal.
  void set_searched(std::map<PlanKey, std::size_t>::iterator entry, std::size_t cells);
  static std::uint64_t entry_digest(const PlanKey& key, std::size_t cells);

  std::map<PlanKey, std::size_t> searched_cells_;
  std::uint64_t digest_ = 0;  ///< the sum of entry_digest over the entries: order-free, updated per change
  std::size_t field_descents_ = 0;
};

/// How an agent pushed off its leg gets back on its path.
enum class Rejoin {
  walk_on,         ///< the waypoint is in sight: walk straight to it from here
  back_to_corner,  ///< the start of the leg (the corner last passed) is in sight: return there first
  replan,          ///< neither: plan again
};

/// How far from an unusable start or goal the planner looks for a usable cell, m.
inline constexpr double kSnapDistance = 1.0;

class PathPlanner {
 public:
  /// The grid and field must outlive the planner.
  PathPlanner(const OccupancyGrid& grid, const DistanceField& field);

  /// Waypoints from start (exclusive) to goal (inclusive, exact), or nothing when the goal cannot be
  /// reached by a disc of `radius`. `blocked_cells` are closed doors and other temporary obstacles
  /// (indices into the grid). `history` is the caller's (see above); updated.
  std::optional<std::vector<Vec2>> plan(const Vec2& start, const Vec2& goal, double radius,
                                        const std::vector<std::size_t>& blocked_cells,
                                        PlanningHistory& history) const;
  /// The same for a one-off request (no history: always a search).
  std::optional<std::vector<Vec2>> plan(const Vec2& start, const Vec2& goal, double radius,
                                        const std::vector<std::size_t>& blocked_cells = {}) const;

  /// What an agent at `position`, pushed off the leg from `leg_start` to `waypoint`, should do, when
  /// a disc of `clearance` must pass on the straight way.
  Rejoin rejoin(const Vec2& position, const Vec2& leg_start, const Vec2& waypoint, double clearance,
                const std::vector<std::size_t>& blocked_cells = {}) const;

  /// True when a disc of `radius` can move in a straight line from a to b.
  bool line_of_sight(const Vec2& a, const Vec2& b, double radius,
                     const std::vector<std::size_t>& blocked_cells = {}) const;

  /// Whether a disc of `radius` centred in the cell fits.
  bool traversable(std::size_t cell, double radius, const std::vector<std::size_t>& blocked_cells = {}) const;
  /// The cell nearest to `cell` (itself, when it is) where a disc of `radius` fits, within
  /// kSnapDistance: where a start or goal on a wall is taken from.
  std::optional<std::size_t> nearest_traversable(std::size_t cell, double radius,
                                                 const std::vector<std::size_t>& blocked_cells = {}) const;

 private:
  /// The cost-to-go field of a goal, from the shared memo or computed now.
  std::shared_ptr<const std::vector<float>> cost_to_go(const PlanKey& key, double radius) const;
  /// Grid cells from start (exclusive) to goal; `expanded` counts the cells the search took off its queue.
  std::optional<std::vector<std::size_t>> a_star(std::size_t start_cell, std::size_t goal_cell, double radius,
                                                 const std::vector<std::size_t>& blocked_cells,
                                                 std::size_t& expanded) const;
  bool diagonal_allowed(CellIndex from, int dx, int dy, double radius, const std::vector<std::size_t>& blocked) const;

  const OccupancyGrid& grid_;
  const DistanceField& field_;
  mutable std::mutex mutex_;
  mutable std::list<PlanKey> recency_;
  mutable std::map<PlanKey, std::shared_ptr<const std::vector<float>>> cache_;
};

}  // namespace hrisim::world
