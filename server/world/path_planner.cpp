#include "world/path_planner.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <deque>
#include <limits>
#include <queue>
#include <tuple>

namespace hrisim::world {
namespace {

constexpr float kUnreachable = std::numeric_limits<float>::infinity();
constexpr int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
constexpr int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
constexpr float kStep[8] = {1.0f, 1.0f, 1.0f, 1.0f, 1.41421356f, 1.41421356f, 1.41421356f, 1.41421356f};

/// Blocked cells in order, as traversable()'s binary search needs them.
std::vector<std::size_t> sorted(std::vector<std::size_t> cells) {
  std::sort(cells.begin(), cells.end());
  return cells;
}

}  // namespace

PathPlanner::PathPlanner(const OccupancyGrid& grid, const DistanceField& field) : grid_(grid), field_(field) {}

void PlanningHistory::hash(core::StateHasher& hasher) const {
  hasher.add(static_cast<std::uint64_t>(searched_cells_.size())).add(static_cast<std::uint64_t>(field_descents_)).add(digest_);
}

std::uint64_t PlanningHistory::entry_digest(const PlanKey& key, std::size_t cells) {
  const auto& [goal, radius, blocked] = key;
  core::StateHasher hasher;
  hasher.add(static_cast<std::uint64_t>(goal)).add(radius).add(static_cast<std::uint64_t>(blocked.size()));
  for (const std::size_t cell : blocked) hasher.add(static_cast<std::uint64_t>(cell));
  return hasher.add(static_cast<std::uint64_t>(cells)).value();
}

std::map<PlanKey, std::size_t>::iterator PlanningHistory::entry(const PlanKey& key) {
  auto found = searched_cells_.find(key);
  if (found != searched_cells_.end()) return found;
  if (searched_cells_.size() >= kPlanningHistoryGoals) clear();
  digest_ += entry_digest(key, 0);
  return searched_cells_.emplace(key, 0).first;
}

void PlanningHistory::set_searched(std::map<PlanKey, std::size_t>::iterator entry, std::size_t cells) {
  if (entry->second == cells) return;
  digest_ += entry_digest(entry->first, cells) - entry_digest(entry->first, entry->second);
  entry->second = cells;
}

bool PathPlanner::traversable(std::size_t cell, double radius, const std::vector<std::size_t>& blocked_cells) const {
  // The nearest blocked cell reaches half a cell towards us.
  if (field_.distance(cell) - 0.5 * grid_.resolution() < radius) return false;
  return !std::binary_search(blocked_cells.begin(), blocked_cells.end(), cell);
}

bool PathPlanner::line_of_sight(const Vec2& a, const Vec2& b, double radius,
                                const std::vector<std::size_t>& blocked_cells) const {
  // A segment that leaves the map is not clear; checked first, so that its length stays within the map's.
  if (!grid_.in_bounds(grid_.cell_of(a)) || !grid_.in_bounds(grid_.cell_of(b))) return false;
  const double length = (b - a).norm();
  const int samples = std::max(1, static_cast<int>(std::ceil(length / (0.5 * grid_.resolution()))));
  for (int i = 0; i <= samples; ++i) {
    const CellIndex c = grid_.cell_of(a + (b - a) * (static_cast<double>(i) / samples));
    if (!grid_.in_bounds(c) || !traversable(grid_.index(c), radius, blocked_cells)) return false;
  }
  return true;
}

Rejoin PathPlanner::rejoin(const Vec2& position, const Vec2& leg_start, const Vec2& waypoint, double clearance,
                           const std::vector<std::size_t>& blocked_cells) const {
  const std::vector<std::size_t> blocked = sorted(blocked_cells);
  if (line_of_sight(position, waypoint, clearance, blocked)) return Rejoin::walk_on;
  if (line_of_sight(position, leg_start, clearance, blocked)) return Rejoin::back_to_corner;
  return Rejoin::replan;
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

std::shared_ptr<const std::vector<float>> PathPlanner::cost_to_go(const PlanKey& key, double radius) const {
  {
    std::lock_guard lock(mutex_);
    if (const auto found = cache_.find(key); found != cache_.end()) {
      recency_.remove(key);
      recency_.push_front(key);
      return found->second;
    }
  }
  const std::size_t goal_cell = std::get<0>(key);
  const std::vector<std::size_t>& blocked_cells = std::get<2>(key);
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
      if (k >= 4 && !diagonal_allowed(here, kDx[k], kDy[k], radius, blocked_cells)) continue;
      const float candidate = cost_here + kStep[k];
      if (candidate < (*cost)[next_index]) {
        (*cost)[next_index] = candidate;
        open.push({candidate, next_index});
      }
    }
  }
  std::lock_guard lock(mutex_);
  if (!cache_.emplace(key, cost).second) return cost;  // another caller computed the same field meanwhile
  recency_.push_front(key);
  while (recency_.size() > kPlannerCacheSize) {
    cache_.erase(recency_.back());
    recency_.pop_back();
  }
  return cost;
}

bool PathPlanner::diagonal_allowed(CellIndex from, int dx, int dy, double radius,
                                   const std::vector<std::size_t>& blocked) const {
  // No cutting corners: both orthogonal neighbours must be passable too.
  const CellIndex side_x{from.x + dx, from.y}, side_y{from.x, from.y + dy};
  return grid_.in_bounds(side_x) && grid_.in_bounds(side_y) && traversable(grid_.index(side_x), radius, blocked) &&
         traversable(grid_.index(side_y), radius, blocked);
}

std::optional<std::vector<std::size_t>> PathPlanner::a_star(std::size_t start_cell, std::size_t goal_cell, double radius,
                                                            const std::vector<std::size_t>& blocked_cells,
                                                            std::size_t& expanded) const {
  const CellIndex goal = grid_.cell_at(goal_cell);
  auto heuristic = [&](CellIndex c) {
    const int dx = std::abs(c.x - goal.x), dy = std::abs(c.y - goal.y);
    return static_cast<float>(std::max(dx, dy) + (kStep[4] - 1.0f) * std::min(dx, dy));  // octile distance
  };
  // Per-thread scratch the size of the grid; a search stamp marks which entries are current, so
  // nothing is cleared between searches.
  struct Scratch {
    std::vector<float> cost;
    std::vector<std::uint32_t> parent;
    std::vector<std::uint32_t> stamp;
    std::uint32_t search = 0;
  };
  thread_local Scratch scratch;
  if (scratch.stamp.size() != grid_.size()) {
    scratch.cost.assign(grid_.size(), 0.0f);
    scratch.parent.assign(grid_.size(), 0);
    scratch.stamp.assign(grid_.size(), 0);
    scratch.search = 0;
  }
  if (++scratch.search == 0) {  // wrapped around: forget every old stamp
    std::fill(scratch.stamp.begin(), scratch.stamp.end(), 0);
    scratch.search = 1;
  }
  const std::uint32_t search = scratch.search;
  auto known_cost = [&](std::size_t index) {
    return scratch.stamp[index] == search ? scratch.cost[index] : kUnreachable;
  };
  // Smallest f first, then the deepest (largest g), then the lowest cell: deterministic. Non-negative
  // floats order like their bit patterns, so f and g pack into one integer key.
  using Entry = std::pair<std::uint64_t, std::uint32_t>;
  auto entry = [](float f, float g, std::size_t cell) {
    const std::uint64_t key = static_cast<std::uint64_t>(std::bit_cast<std::uint32_t>(f)) << 32 |
                              (0xFFFFFFFFu - std::bit_cast<std::uint32_t>(g));
    return Entry{key, static_cast<std::uint32_t>(cell)};
  };
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  scratch.stamp[start_cell] = search;
  scratch.cost[start_cell] = 0.0f;
  open.push(entry(heuristic(grid_.cell_at(start_cell)), 0.0f, start_cell));
  while (!open.empty()) {
    const std::size_t index = open.top().second;
    const float g = std::bit_cast<float>(static_cast<std::uint32_t>(0xFFFFFFFFu - (open.top().first & 0xFFFFFFFFu)));
    open.pop();
    if (g > known_cost(index)) continue;
    ++expanded;
    if (index == goal_cell) {
      std::vector<std::size_t> path;
      for (std::size_t at = goal_cell; at != start_cell; at = scratch.parent[at]) path.push_back(at);
      std::reverse(path.begin(), path.end());
      return path;
    }
    const CellIndex here = grid_.cell_at(index);
    for (int k = 0; k < 8; ++k) {
      const CellIndex next{here.x + kDx[k], here.y + kDy[k]};
      if (!grid_.in_bounds(next)) continue;
      const std::size_t next_index = grid_.index(next);
      const float candidate = g + kStep[k];
      if (known_cost(next_index) <= candidate) continue;
      if (!traversable(next_index, radius, blocked_cells)) continue;
      if (k >= 4 && !diagonal_allowed(here, kDx[k], kDy[k], radius, blocked_cells)) continue;
      scratch.stamp[next_index] = search;
      scratch.cost[next_index] = candidate;
      scratch.parent[next_index] = static_cast<std::uint32_t>(index);
      open.push(entry(candidate + heuristic(next), candidate, next_index));
    }
  }
  return std::nullopt;
}

std::optional<std::vector<Vec2>> PathPlanner::plan(const Vec2& start, const Vec2& goal, double radius,
                                                   const std::vector<std::size_t>& blocked_cells) const {
  PlanningHistory one_off;
  return plan(start, goal, radius, blocked_cells, one_off);
}

std::optional<std::vector<Vec2>> PathPlanner::plan(const Vec2& start, const Vec2& goal, double radius,
                                                   const std::vector<std::size_t>& blocked_cells,
                                                   PlanningHistory& history) const {
  const std::vector<std::size_t> blocked = sorted(blocked_cells);
  const CellIndex start_index = grid_.cell_of(start), goal_index = grid_.cell_of(goal);
  if (!grid_.in_bounds(start_index) || !grid_.in_bounds(goal_index)) return std::nullopt;
  if (line_of_sight(start, goal, radius, blocked)) return std::vector<Vec2>{goal};
  const auto start_cell = nearest_traversable(grid_.index(start_index), radius, blocked);
  const auto goal_cell = nearest_traversable(grid_.index(goal_index), radius, blocked);
  if (!start_cell || !goal_cell) return std::nullopt;
  const PlanKey key{*goal_cell, static_cast<int>(std::lround(radius * 1000.0)), blocked};
  const auto searched = history.entry(key);
  std::vector<std::size_t> cells;
  if (searched->second >= grid_.size()) {
    ++history.field_descents_;
    const auto cost = cost_to_go(key, radius);
    if ((*cost)[*start_cell] == kUnreachable) return std::nullopt;
    // Descend the cost-to-go field from the start to the goal cell.
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
      cells.push_back(index);
    }
  } else {
    std::size_t searched_cells = searched->second;
    auto found = a_star(*start_cell, *goal_cell, radius, blocked, searched_cells);
    history.set_searched(searched, searched_cells);
    if (!found) return std::nullopt;
    cells = std::move(*found);
  }

  // Corners of the grid path (where its direction changes), then the goal itself.
  std::vector<Vec2> corners;
  for (std::size_t i = 0; i + 1 < cells.size(); ++i) {
    const CellIndex previous = grid_.cell_at(i == 0 ? *start_cell : cells[i - 1]);
    const CellIndex here = grid_.cell_at(cells[i]), next = grid_.cell_at(cells[i + 1]);
    if (here.x - previous.x != next.x - here.x || here.y - previous.y != next.y - here.y) {
      corners.push_back(grid_.center_of(here));
    }
  }
  corners.push_back(goal);

  // Keep only the corners where the straight line of sight ends.
  std::vector<Vec2> path;
  Vec2 anchor = start;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const bool last = i + 1 == corners.size();
    if (last || !line_of_sight(anchor, corners[i + 1], radius, blocked)) {
      path.push_back(corners[i]);
      anchor = corners[i];
    }
  }
  return path;
}

}  // namespace hrisim::world
