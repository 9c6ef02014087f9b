#include "world/path_planner.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <queue>

namespace hrisim::world {
namespace {

constexpr float kUnreachable = std::numeric_limits<float>::infinity();
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
constexpr float kStep[8] = {1.0f, 1.0f, 1.0f, 1.0f, 1.41421356f, 1.41421356f, 1.41421356f, 1.41421356f};
/// How far from an unusable start or goal the planner looks for a usable cell.
constexpr double kSnapDistance = 1.0;

}  // namespace

PathPlanner::PathPlanner(const OccupancyGrid& grid, const DistanceField& field) : grid_(grid), field_(field) {}

bool PathPlanner::traversable(std::size_t cell, double radius, const std::vector<std::size_t>& blocked_cells) const {
  // The nearest blocked cell reaches half a cell towards us.
  if (field_.distance(cell) - 0.5 * grid_.resolution() < radius) return false;
  return !std::binary_search(blocked_cells.begin(), blocked_cells.end(), cell);
}

bool PathPlanner::line_of_sight(const Vec2& a, const Vec2& b, double radius,
                                const std::vector<std::size_t>& blocked_cells) const {
  const double length = (b - a).norm();
  const int samples = std::max(1, static_cast<int>(std::ceil(length / (0.5 * grid_.resolution()))));
  for (int i = 0; i <= samples; ++i) {
    const CellIndex c = grid_.cell_of(a + (b - a) * (static_cast<double>(i) / samples));
    if (!grid_.in_bounds(c) || !traversable(grid_.index(c), radius, blocked_cells)) return false;
  }
  return true;
}

std::optional<std::size_t> PathPlanner::nearest_traversable(std::size_t cell, double radius,
                                                            const std::vector<std::size_t>& blocked_cells) const {
  if (traversable(cell, radius, blocked_cells)) return cell;
  const int reach = static_cast<int>(std::ceil(kSnapDistance / grid_.resolution()));
  const CellIndex centre = grid_.cell_at(cell);
  std::optional<std::size_t> best;
  int best_distance = std::numeric_limits<int>::max();
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      const CellIndex c{centre.x + dx, centre.y + dy};
      const int distance = dx * dx + dy * dy;
      if (distance >= best_distance || distance > reach * reach || !grid_.in_bounds(c)) continue;
      if (traversable(grid_.index(c), radius, blocked_cells)) {
        best = grid_.index(c);
        best_distance = distance;
      }
    }
  }
  return best;
}

std::shared_ptr<const std::vector<float>> PathPlanner::cost_to_go(std::size_t goal_cell, double radius,
                                                                  const std::vector<std::size_t>& blocked_cells) const {
  CacheKey key{goal_cell, static_cast<int>(std::lround(radius * 1000.0)), blocked_cells};
  {
    std::lock_guard lock(mutex_);
    if (const auto found = cache_.find(key); found != cache_.end()) {
      recency_.remove(key);
      recency_.push_front(key);
      return found->second;
    }
  }
  auto cost = std::make_shared<std::vector<float>>(grid_.size(), kUnreachable);
  using Entry = std::pair<float, std::size_t>;  // ties broken by cell index: deterministic
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  (*cost)[goal_cell] = 0.0f;
  open.push({0.0f, goal_cell});
  while (!open.empty()) {
    const auto [cost_here, index] = open.top();
    open.pop();
    if (cost_here > (*cost)[index]) continue;
    const CellIndex here = grid_.cell_at(index);
    for (int k = 0; k < 8; ++k) {
      const CellIndex next{here.x + kDx[k], here.y + kDy[k]};
      if (!grid_.in_bounds(next)) continue;
      const std::size_t next_index = grid_.index(next);
      if (!traversable(next_index, radius, blocked_cells)) continue;
      if (k >= 4 && (!traversable(grid_.index({here.x + kDx[k], here.y}), radius, blocked_cells) ||
                     !traversable(grid_.index({here.x, here.y + kDy[k]}), radius, blocked_cells))) {
        continue;  // no cutting corners
      }
      const float candidate = cost_here + kStep[k];
      if (candidate < (*cost)[next_index]) {
        (*cost)[next_index] = candidate;
        open.push({candidate, next_index});
      }
    }
  }
  std::lock_guard lock(mutex_);
  cache_[key] = cost;
  recency_.push_front(key);
  while (recency_.size() > kPlannerCacheSize) {
    cache_.erase(recency_.back());
    recency_.pop_back();
  }
  return cost;
}

std::optional<std::vector<Vec2>> PathPlanner::plan(const Vec2& start, const Vec2& goal, double radius,
                                                   const std::vector<std::size_t>& blocked_cells) const {
  std::vector<std::size_t> blocked = blocked_cells;
  std::sort(blocked.begin(), blocked.end());
  const CellIndex start_index = grid_.cell_of(start), goal_index = grid_.cell_of(goal);
  if (!grid_.in_bounds(start_index) || !grid_.in_bounds(goal_index)) return std::nullopt;
  const auto start_cell = nearest_traversable(grid_.index(start_index), radius, blocked);
  const auto goal_cell = nearest_traversable(grid_.index(goal_index), radius, blocked);
  if (!start_cell || !goal_cell) return std::nullopt;
  const auto cost = cost_to_go(*goal_cell, radius, blocked);
  if ((*cost)[*start_cell] == kUnreachable) return std::nullopt;

  // Descend the cost-to-go field from the start to the goal cell.
  std::vector<Vec2> cells;
  std::size_t index = *start_cell;
  while (index != *goal_cell) {
    const CellIndex here = grid_.cell_at(index);
    std::size_t best = index;
    for (int k = 0; k < 8; ++k) {
      const CellIndex next{here.x + kDx[k], here.y + kDy[k]};
      if (grid_.in_bounds(next) && (*cost)[grid_.index(next)] < (*cost)[best]) best = grid_.index(next);
    }
    if (best == index) return std::nullopt;  // cannot happen on a consistent field; refuse rather than loop
    index = best;
    cells.push_back(grid_.center_of(grid_.cell_at(index)));
  }
  cells.push_back(goal);

  // Keep only the cells where the straight line of sight ends.
  std::vector<Vec2> path;
  Vec2 anchor = start;
  for (std::size_t i = 0; i < cells.size(); ++i) {
    const bool last = i + 1 == cells.size();
    if (last || !line_of_sight(anchor, cells[i + 1], radius, blocked)) {
      path.push_back(cells[i]);
      anchor = cells[i];
    }
  }
  return path;
}

}  // namespace hrisim::world
