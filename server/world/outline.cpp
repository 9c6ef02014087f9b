#include "world/outline.hpp"

namespace hrisim::world {

std::vector<Segment> occupied_outline(const OccupancyGrid& grid) {
  std::vector<Segment> segments;
  const double r = grid.resolution();
  const Vec2& origin = grid.origin();
  auto occupied = [&](int x, int y) { return grid.at({x, y}) == Cell::occupied; };
  // An edge lies between two cells when exactly one of them is occupied; walk each grid line and
  // emit runs of consecutive such edges.
  auto emit_runs = [&](int lines, int cells, auto edge_here, auto segment_of) {
    for (int line = 0; line <= lines; ++line) {
      int run_start = -1;
      for (int cell = 0; cell <= cells; ++cell) {
        const bool edge = cell < cells && edge_here(line, cell);
        if (edge && run_start < 0) run_start = cell;
        if (!edge && run_start >= 0) {
          segments.push_back(segment_of(line, run_start, cell));
          run_start = -1;
        }
      }
    }
  };
  // Horizontal lines y = line, between rows line - 1 and line.
  emit_runs(grid.height(), grid.width(), [&](int line, int x) { return occupied(x, line - 1) != occupied(x, line); },
            [&](int line, int from, int to) {
              return Segment{origin + Vec2(from * r, line * r), origin + Vec2(to * r, line * r)};
            });
  // Vertical lines x = line, between columns line - 1 and line.
  emit_runs(grid.width(), grid.height(), [&](int line, int y) { return occupied(line - 1, y) != occupied(line, y); },
            [&](int line, int from, int to) {
              return Segment{origin + Vec2(line * r, from * r), origin + Vec2(line * r, to * r)};
            });
  return segments;
}

void append_edges(const std::vector<Vec2>& polygon, std::vector<Segment>& segments) {
  for (std::size_t i = 0; i < polygon.size(); ++i) segments.push_back({polygon[i], polygon[(i + 1) % polygon.size()]});
}

}  // namespace hrisim::world
