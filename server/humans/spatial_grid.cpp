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

void SpatialGrid::nearest_within(const Vec2& p, double range, std::size_t count, std::uint32_t excluded,
                                 std::vector<std::pair<double, std::uint32_t>>& nearest) const {
  nearest.clear();
  if (sorted_positions_.empty() || count == 0) return;
  const int x0 = std::max(0, cell_x(p.x() - range)), x1 = std::min(columns_ - 1, cell_x(p.x() + range));
  const int y0 = std::max(0, cell_y(p.y() - range)), y1 = std::min(rows_ - 1, cell_y(p.y() + range));
  if (count >= items_.size()) {
    // All within range: gathered, then sorted once (a crush has dozens, which sinking one by one
    // into place would cost quadratically). The order is the same: (distance, index) is total.
    const double limit = range * range;
    for (int y = y0; y <= y1; ++y) {
      const std::size_t row = static_cast<std::size_t>(y) * columns_;
      for (std::uint32_t k = cell_start_[row + x0]; k < cell_start_[row + x1 + 1]; ++k) {
        const double distance = (sorted_positions_[k] - p).squaredNorm();
        if (distance <= limit && items_[k] != excluded) nearest.emplace_back(distance, items_[k]);
      }
    }
    std::sort(nearest.begin(), nearest.end());
    return;
  }
  double limit = range * range;  // the k-th nearest's squared distance once k are known
  const auto scan = [&](int x, int y) __attribute__((always_inline)) {
    const double low_x = low_.x() + x * cell_size_, low_y = low_.y() + y * cell_size_;
    const double gap_x = std::max(std::max(low_x - p.x(), p.x() - (low_x + cell_size_)), 0.0);
    const double gap_y = std::max(std::max(low_y - p.y(), p.y() - (low_y + cell_size_)), 0.0);
    if (gap_x * gap_x + gap_y * gap_y > limit) return;
    const std::size_t cell = static_cast<std::size_t>(y) * columns_ + x;
    for (std::uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
      const double distance = (sorted_positions_[k] - p).squaredNorm();
      if (distance > limit || items_[k] == excluded) continue;
      const std::pair candidate{distance, items_[k]};
      if (nearest.size() == count) {
        if (!(candidate < nearest.back())) continue;
        nearest.pop_back();
      }
      nearest.push_back(candidate);  // then sink it to its place: the list is short
      for (std::size_t j = nearest.size() - 1; j > 0 && nearest[j] < nearest[j - 1]; --j) std::swap(nearest[j], nearest[j - 1]);
      if (nearest.size() == count) limit = nearest.back().first;
    }
  };
  // p's own cell first: its neighbours there set a tight limit, and most other cells are then skipped.
  const int own_x = cell_x(p.x()), own_y = cell_y(p.y());
  const bool inside = own_x >= 0 && own_x < columns_ && own_y >= 0 && own_y < rows_;
  if (inside) scan(own_x, own_y);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      if (!inside || x != own_x || y != own_y) scan(x, y);
    }
  }
}

}  // namespace hrisim::humans
