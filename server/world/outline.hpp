#pragma once
// The static map as line segments, for range sensors: the exact edges of geometric obstacles, and for
// maps that come as images, the boundary of their occupied cells merged into maximal straight runs.
#include <limits>
#include <vector>

#include "world/occupancy_grid.hpp"

namespace hrisim::world {

struct Segment {
  Vec2 a = Vec2::Zero();
  Vec2 b = Vec2::Zero();
  /// The boundary of a solid, free space on its left (from a towards b): nothing outside the solid
  /// can see its right side, so sensors skip it from there.
  bool one_sided = false;
  /// Height of the solid's top, m: range sensors mounted higher see over it.
  double top = std::numeric_limits<double>::infinity();
};

/// Boundary between occupied cells and free or unknown ones (a laser passes unknown space), as
/// horizontal and vertical runs along cell edges, each as long as it can be; one-sided.
std::vector<Segment> occupied_outline(const OccupancyGrid& grid);

/// Appends the edges of a closed polygon (a solid `top` high), one-sided whichever way it winds.
void append_edges(const std::vector<Vec2>& polygon, std::vector<Segment>& segments,
                  double top = std::numeric_limits<double>::infinity());

}  // namespace hrisim::world
