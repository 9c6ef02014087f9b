#include "humans/spatial_grid.hpp"

#include <algorithm>

namespace hrisim::humans {

/// Agents spread wider than this many cells per side share cells instead (memory bound).
constexpr int kMaxCellsPerSide = 4096;

void SpatialGrid::rebuild(std::span<const Vec2> positions) {
  items_.resize(positions.size());
  if (positions.empty()) return;
  Vec2 high = positions.front();
  low_ = positions.front();
  for (const Vec2& p : positions) {
    low_ = low_.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const double extent = std::max(high.x() - low_.x(), high.y() - low_.y());
  cell_size_ = std::max(base_cell_size_, extent / kMaxCellsPerSide);
  columns_ = cell_x(high.x()) + 1;
  rows_ = cell_y(high.y()) + 1;
  cell_start_.assign(static_cast<std::size_t>(columns_) * rows_ + 1, 0);
  std::vector<std::uint32_t> cell_of(positions.size());
  for (std::size_t i = 0; i < positions.size(); ++i) {
    cell_of[i] = static_cast<std::uint32_t>(cell_y(positions[i].y()) * columns_ + cell_x(positions[i].x()));
    ++cell_start_[cell_of[i] + 1];
  }
  for (std::size_t c = 1; c < cell_start_.size(); ++c) cell_start_[c] += cell_start_[c - 1];
  std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < positions.size(); ++i) items_[fill[cell_of[i]]++] = static_cast<std::uint32_t>(i);
  sorted_positions_.resize(positions.size());
  for (std::size_t k = 0; k < items_.size(); ++k) sorted_positions_[k] = positions[items_[k]];
}

}  // namespace hrisim::humans
