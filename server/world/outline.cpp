#include "world/outline.hpp"

namespace hrisim::world {

std::vector<Segment> occupied_outline(const OccupancyGrid& grid) {
  std::vector<Segment> segments;
  const double r = grid.resolution();
  const Vec2& origin = grid.origin();
  auto occupied = [&](int x, int y) { return grid.at({x, y}) == Cell::occupied; };
  // An edge lies between two cells when exactly one of them is occupied; walk each grid line and
  // emit runs of consecutive such edges.
  // `side(line, cell)` is +1 where the occupied cell is before the line (below or left), -1 where it
  // is after, 0 where there is no edge; a run continues while the side stays the same.
  auto emit_runs = [&](int lines, int cells, auto side, auto segment_of) {
    for (int line = 0; line <= lines; ++line) {
      int run_start = -1, run_side = 0;
      for (int cell = 0; cell <= cells; ++cell) {
        const int here = cell < cells ? side(line, cell) : 0;
        if (here != run_side && run_side != 0) {
          segments.push_back(segment_of(line, run_start, cell, run_side));
          run_start = -1;
        }
        if (here != 0 && here != run_side) run_start = cell;
        run_side = here;
      }
    }
  };
  auto side = [&](bool before, bool after) { return before == after ? 0 : before ? 1 : -1; };
  // Horizontal lines y = line, between rows line - 1 and line; free space on the left of a → b.
  emit_runs(grid.height(), grid.width(), [&](int line, int x) { return side(occupied(x, line - 1), occupied(x, line)); },
            [&](int line, int from, int to, int occupied_below) {
              const Vec2 low = origin + Vec2(from * r, line * r), high = origin + Vec2(to * r, line * r);
              return occupied_below > 0 ? Segment{low, high, true} : Segment{high, low, true};
            });
  // Vertical lines x = line, between columns line - 1 and line.
  emit_runs(grid.width(), grid.height(), [&](int line, int y) { return side(occupied(line - 1, y), occupied(line, y)); },
            [&](int line, int from, int to, int occupied_left) {
              const Vec2 low = origin + Vec2(line * r, from * r), high = origin + Vec2(line * r, to * r);
              return occupied_left > 0 ? Segment{high, low, true} : Segment{low, high, true};
            });
  return segments;
}

void append_edges(const std::vector<Vec2>& polygon, std::vector<Segment>& segments, double top) {
  double twice_area = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) twice_area += core::cross(polygon[i], polygon[(i + 1) % polygon.size()]);
  // Counter-clockwise polygons have their inside on the left of each edge: walk them backwards.
  const bool reverse = twice_area > 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[(i + 1) % polygon.size()];
    segments.push_back(reverse ? Segment{b, a, true, top} : Segment{a, b, true, top});
  }
}

}  // namespace hrisim::world
