#pragma once
// Uniform grid over agent positions, rebuilt every step (counting sort, O(n)), for neighbour queries
// without O(n²) scans. Items within a cell keep their index order, so queries are deterministic.
// Positions are also kept in cell order, so scans read memory in sequence.
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

  /// Calls f(a, b) once for every unordered pair of items within `range` of each other, in a fixed
  /// order; a scan of half the neighbouring cells of each cell.
  template <class F>
  void for_each_pair_within(double range, F&& f) const {
    const int reach = static_cast<int>(std::ceil(range / cell_size_));
    const double range_squared = range * range;
    for (int y = 0; y < rows_; ++y) {
      for (int x = 0; x < columns_; ++x) {
        const std::size_t cell = static_cast<std::size_t>(y) * columns_ + x;
        if (cell_start_[cell] == cell_start_[cell + 1]) continue;
        for (int dy = 0; dy <= reach && y + dy < rows_; ++dy) {
          for (int dx = dy == 0 ? 0 : -reach; dx <= reach; ++dx) {
            if (x + dx < 0 || x + dx >= columns_) continue;
            const std::size_t other = cell + static_cast<std::size_t>(dy) * columns_ + dx;
            for (std::uint32_t a = cell_start_[cell]; a < cell_start_[cell + 1]; ++a) {
              const Vec2 p = sorted_positions_[a];
              for (std::uint32_t b = other == cell ? a + 1 : cell_start_[other]; b < cell_start_[other + 1]; ++b) {
                if ((sorted_positions_[b] - p).squaredNorm() <= range_squared) f(items_[a], items_[b]);
              }
            }
          }
        }
      }
    }
  }

  /// Calls f(index) for every item within `range` of p (exact distance test), in a fixed order.
  template <class F>
  void for_each_within(const Vec2& p, double range, F&& f) const {
    if (sorted_positions_.empty()) return;
    const int x0 = std::max(0, cell_x(p.x() - range)), x1 = std::min(columns_ - 1, cell_x(p.x() + range));
    const int y0 = std::max(0, cell_y(p.y() - range)), y1 = std::min(rows_ - 1, cell_y(p.y() + range));
    const double range_squared = range * range;
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const std::size_t cell = static_cast<std::size_t>(y) * columns_ + x;
        for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
          if ((sorted_positions_[k] - p).squaredNorm() <= range_squared) f(items_[k]);
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
  std::vector<std::uint32_t> cell_start_;
  std::vector<std::uint32_t> items_;  ///< item indices in cell order
  std::vector<Vec2> sorted_positions_;  ///< their positions, in the same order
};

}  // namespace hrisim::humans
