#pragma once
// Uniform grid over agent positions, rebuilt every step (counting sort, O(n)), for neighbour queries
// without O(n²) scans. Items within a cell keep their index order, so queries are deterministic.
// Positions are also kept in cell order, so scans read memory in sequence.
#include <algorithm>
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

  /// Items in cell order ("slots"): slot k holds item items()[k] at sorted_positions()[k].
  std::span<const std::uint32_t> items() const { return items_; }
  std::span<const Vec2> sorted_positions() const { return sorted_positions_; }

  /// Calls f(a, begin, end) for slots a and runs of slots [begin, end) such that every unordered pair
  /// of slots within `range` of each other appears exactly once as a and a member of one of a's runs.
  /// Runs also hold slots further away (callers test the distance); each is contiguous memory: the
  /// cells of a row within reach. A half stencil: runs only reach forwards in cell order. Slots a come
  /// in increasing order; only those in [first, last) when given, so parts of the slots can be
  /// scanned apart and their pairs put together in the order one scan gives.
  template <class F>
  void for_each_candidate_run(double range, F&& f, std::uint32_t first = 0, std::uint32_t last = UINT32_MAX) const {
    const int reach = static_cast<int>(std::ceil(range / cell_size_));
    const auto run_end = [&](int row, int x) {
      return cell_start_[static_cast<std::size_t>(row) * columns_ + std::min(x + reach, columns_ - 1) + 1];
    };
    for (int y = 0; y < rows_; ++y) {
      for (int x = 0; x < columns_; ++x) {
        const std::size_t cell = static_cast<std::size_t>(y) * columns_ + x;
        if (cell_start_[cell] >= last) return;
        if (cell_start_[cell + 1] <= first) continue;
        for (std::uint32_t a = std::max(cell_start_[cell], first); a < std::min(cell_start_[cell + 1], last); ++a) {
          f(a, a + 1, run_end(y, x));  // the rest of its own cell and the cells to its right
          for (int row = y + 1; row <= y + reach && row < rows_; ++row) {
            f(a, cell_start_[static_cast<std::size_t>(row) * columns_ + std::max(x - reach, 0)], run_end(row, x));
          }
        }
      }
    }
  }

  /// The `count` items nearest to p within `range` (other than `excluded`), nearest first and ties in
  /// index order, as (squared distance, index) into `nearest`. Cells beyond the current k-th nearest are
  /// skipped, so dense crowds cost little more than sparse ones.
  void nearest_within(const Vec2& p, double range, std::size_t count, std::uint32_t excluded,
                      std::vector<std::pair<double, std::uint32_t>>& nearest) const;

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
