#pragma once
// The static map as a grid of free / occupied / unknown cells, and its distance field: for every
// cell, how far the nearest blocked cell is and where it lies. Planning inflates obstacles by an
// agent's radius through the distance field; obstacle forces read the nearest obstacle point from it.
#include <cstdint>
#include <optional>
#include <vector>

#include "core/math.hpp"

namespace hrisim::world {

using core::Vec2;

enum class Cell : std::uint8_t { free = 0, occupied = 1, unknown = 2 };

/// Cell size of grids rasterised from scenario geometry, in metres.
inline constexpr double kDefaultGridResolution = 0.05;
/// Most cells a scenario's grid may have (4000 × 4000: a 200 m building at 5 cm); `--max-grid-cells`.
inline constexpr std::int64_t kDefaultMaxGridCells = 16'000'000;

struct CellIndex {
  int x = 0;
  int y = 0;
  bool operator==(const CellIndex&) const = default;
};

class OccupancyGrid {
 public:
  /// `origin` is the map-frame position of the lower-left corner of cell (0, 0); rows grow along +y.
  OccupancyGrid(double resolution, Vec2 origin, int width, int height, Cell fill = Cell::free);

  double resolution() const { return resolution_; }
  const Vec2& origin() const { return origin_; }
  int width() const { return width_; }
  int height() const { return height_; }
  std::size_t size() const { return cells_.size(); }

  bool in_bounds(CellIndex c) const { return c.x >= 0 && c.y >= 0 && c.x < width_ && c.y < height_; }
  std::size_t index(CellIndex c) const { return static_cast<std::size_t>(c.y) * width_ + c.x; }
  CellIndex cell_at(std::size_t index) const {
    return {static_cast<int>(index % width_), static_cast<int>(index / width_)};
  }
  CellIndex cell_of(const Vec2& p) const;
  Vec2 center_of(CellIndex c) const;

  Cell at(CellIndex c) const { return in_bounds(c) ? cells_[index(c)] : Cell::unknown; }
  void set(CellIndex c, Cell value) {
    if (in_bounds(c)) cells_[index(c)] = value;
  }
  /// Not free: occupied, unknown or outside the map.
  bool blocked(CellIndex c) const { return at(c) != Cell::free; }
  bool blocked(const Vec2& p) const { return blocked(cell_of(p)); }

  /// Marks every cell the closed polygon covers: cells whose centre is inside or whose centre lies
  /// within half a cell of an edge, so thin walls are never lost between cell centres.
  void fill_polygon(const std::vector<Vec2>& polygon, Cell value = Cell::occupied);

 private:
  double resolution_;
  Vec2 origin_;
  int width_;
  int height_;
  std::vector<Cell> cells_;
};

/// For every cell: distance to the centre of the nearest blocked cell (0 inside obstacles) and that
/// cell. Computed once per static map (two-pass nearest-site propagation, exact distances to the
/// propagated sites).
class DistanceField {
 public:
  explicit DistanceField(const OccupancyGrid& grid);

  /// Distance in metres from the cell's centre to the nearest blocked cell's centre; a large value
  /// when the map has no blocked cell.
  double distance(std::size_t index) const { return distance_[index]; }
  double distance(const OccupancyGrid& grid, const Vec2& p) const;
  /// Map-frame position of the nearest blocked cell's centre, if any.
  std::optional<Vec2> nearest_obstacle(const OccupancyGrid& grid, const Vec2& p) const;

 private:
  std::vector<float> distance_;
  std::vector<std::int32_t> nearest_;
};

/// Point-in-polygon (even-odd rule).
bool contains(const std::vector<Vec2>& polygon, const Vec2& p);

}  // namespace hrisim::world
