#include "scenario/reaching.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hrisim::scenario {
namespace {

bool free_for(const Model& model, const Vec2& p, double radius) {
  const world::CellIndex cell = model.grid.cell_of(p);
  return model.grid.in_bounds(cell) && model.planner.traversable(model.grid.index(cell), radius);
}

/// Whether `p` is on the obstacle's own cells: inside it, or within a cell of its outline.
bool on_obstacle(const Model& model, const Obstacle& obstacle, const Vec2& p) {
  if (world::contains(obstacle.polygon, p)) return true;
  for (std::size_t i = 0; i < obstacle.polygon.size(); ++i) {
    const Vec2& a = obstacle.polygon[i];
    const Vec2& b = obstacle.polygon[(i + 1) % obstacle.polygon.size()];
    if ((core::closest_point_on_segment(p, a, b) - p).norm() <= model.grid.resolution()) return true;
  }
  return false;
}

}  // namespace

double sit_down_travel() {
  static const double travel = [] {
    const humans::MotionClip& sit = *humans::builtin_motion("sit_down");
    return -sit.sample(sit.duration()).root.x();
  }();
  return travel;
}

Vec2 seat_spot(const Seat& seat) { return seat.pose.position() + core::heading_vector(seat.pose.theta) * sit_down_travel(); }

std::optional<Vec2> seat_approach(const Model& model, const Seat& seat, double radius) {
  const Vec2 ahead = core::heading_vector(seat.pose.theta);
  const double step = 0.5 * model.grid.resolution();
  // Out from the seat's spot along its way: the step back onto it crosses nothing but the seat's own
  // obstacle (not a wall behind which the map happens to be free).
  for (double d = sit_down_travel(); d <= sit_down_travel() + kSeatApproachReach; d += step) {
    const Vec2 spot = seat.pose.position() + ahead * d;
    if (free_for(model, spot, radius)) return spot;
    if (model.grid.blocked(spot) && !on_obstacle(model, model.obstacles[seat.obstacle], spot)) return std::nullopt;
  }
  return std::nullopt;
}

double reach_heading(const Vec2& spot, const Vec2& item) {
  const double distance = (item - spot).norm();
  return core::direction_to(spot, item) + std::asin(std::min(1.0, kHandSideOffset / distance));
}

std::optional<Vec2> reach_spot(const Model& model, const Vec2& item, const Vec2& from, double radius) {
  const double step = 0.5 * model.grid.resolution();
  for (double distance = kHandReach; distance <= kMaxHandReach; distance += step) {
    std::optional<Vec2> best;
    for (int k = 0; k < kReachDirections; ++k) {
      const double angle = 2.0 * std::numbers::pi * k / kReachDirections;
      const Vec2 spot = item + distance * Vec2(std::cos(angle), std::sin(angle));
      if (free_for(model, spot, radius) && (!best || (spot - from).squaredNorm() < (*best - from).squaredNorm())) best = spot;
    }
    if (best) return best;
  }
  return std::nullopt;
}

}  // namespace hrisim::scenario
