#pragma once
// Uniform grid over agent positions, rebuilt every step (counting sort, O(n)), for neighbour queries
// without O(n²) scans. Items within a cell keep their index order, so queries are deterministic.
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "core/math.hpp"

namespace hrisim::humans {

using core::Vec2;

class SpatialGrid {
 public:
  explicit SpatialGrid(double cell_size) : base_cell_size_(cell_size), cell_size_(cell_size) {}

  void rebuild(std::span<const Vec2> positions);

  /// Calls f(index) for every item within `range` of p (exact distance test), in a fixed order.
  template <class F>
  void for_each_within(const Vec2& p, double range, F&& f) const {
    if (positions_.empty()) return;
    const int x0 = std::max(0, cell_x(p.x() - range)), x1 = std::min(columns_ - 1, cell_x(p.x() + range));
    const int y0 = std::max(0, cell_y(p.y() - range)), y1 = std::min(rows_ - 1, cell_y(p.y() + range));
    const double range_squared = range * range;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const std::size_t cell = static_cast<std::size_t>(y) * columns_ + x;
        for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
          const std::uint32_t index = items_[k];
          if ((positions_[index] - p).squaredNorm() <= range_squared) f(index);
        }
      }
    }
  }

 private:
  int cell_x(double x) const { return static_cast<int>(std::floor((x - low_.x()) / cell_size_)); }
  int cell_y(double y) const { return static_cast<int>(std::floor((y - low_.y()) / cell_size_)); }

  double base_cell_size_;
  double cell_size_;
  Vec2 low_ = Vec2::Zero();
  int columns_ = 0;
  int rows_ = 0;
  std::span<const Vec2> positions_;
  std::vector<std::uint32_t> cell_start_;
  std::vector<std::uint32_t> items_;
};

}  // namespace hrisim::humans
