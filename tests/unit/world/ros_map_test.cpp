#include "world/ros_map.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "core/error.hpp"
#include "support/temp_dir.hpp"

namespace hrisim::world {
namespace {

void write(const std::filesystem::path& path, const std::string& content) {
  std::ofstream(path, std::ios::binary) << content;
}

// A 4×3 map: top row occupied (black), middle row unknown (grey 205), bottom row free (white 254).
std::string small_pgm() {
  std::string pixels;
  pixels += std::string(4, '\x00');
  pixels += std::string(4, '\xcd');
  pixels += std::string(4, '\xfe');
  return "P5\n# written by a test\n4 3\n255\n" + pixels;
}

TEST(RosMap, ClassifiesPixelsAndFlipsRows) {
  testing::TempDir dir;
  write(dir / "m.pgm", small_pgm());
  write(dir / "m.yaml", "image: m.pgm\nresolution: 0.5\norigin: [-1.0, 2.0, 0.0]\nnegate: 0\n"
                        "occupied_thresh: 0.65\nfree_thresh: 0.196\n");
  const OccupancyGrid grid = load_ros_map(dir / "m.yaml");
  EXPECT_EQ(grid.width(), 4);
  EXPECT_EQ(grid.height(), 3);
  EXPECT_DOUBLE_EQ(grid.resolution(), 0.5);
  EXPECT_EQ(grid.at({0, 0}), Cell::free);       // image bottom row → map row 0
  EXPECT_EQ(grid.at({0, 1}), Cell::unknown);
  EXPECT_EQ(grid.at({0, 2}), Cell::occupied);   // image top row → top of the map
  EXPECT_EQ(grid.cell_of({-0.9, 2.1}), (CellIndex{0, 0}));  // origin is the lower-left corner
}

TEST(RosMap, NegateInvertsTheImage) {
  testing::TempDir dir;
  write(dir / "m.pgm", small_pgm());
  write(dir / "m.yaml", "image: m.pgm\nresolution: 0.5\norigin: [0, 0, 0]\nnegate: 1\n");
  const OccupancyGrid grid = load_ros_map(dir / "m.yaml");
  EXPECT_EQ(grid.at({0, 0}), Cell::occupied);
  EXPECT_EQ(grid.at({0, 2}), Cell::free);
}

void expect_error(const std::string& yaml, const std::string& needle) {
  testing::TempDir dir;
  write(dir / "m.pgm", small_pgm());
  write(dir / "m.yaml", yaml);
  try {
    load_ros_map(dir / "m.yaml");
    FAIL() << "expected an error mentioning " << needle;
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    EXPECT_EQ(e.code(), core::ErrorCode::bad_request);
  }
}

TEST(RosMap, ErrorsNameTheLineAndKey) {
  expect_error("image: m.pgm\nresolution: fast\norigin: [0, 0, 0]\n", "m.yaml:2: resolution");
  expect_error("image: m.pgm\nresolution: 0.1\norigin: [0, 0]\n", "m.yaml:3: origin");
  expect_error("image: m.pgm\norigin: [0, 0, 0]\n", "missing key 'resolution'");
  expect_error("image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\ncolour: red\n", "m.yaml:4: unknown key 'colour'");
  expect_error("image: nope.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n", "nope.pgm is not a regular file");
  expect_error("image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nfree_thresh: 0.9\n", "thresholds");
}

TEST(RosMap, TruncatedImageIsRefused) {
  testing::TempDir dir;
  write(dir / "m.pgm", "P5\n4 3\n255\nab");
  write(dir / "m.yaml", "image: m.pgm\nresolution: 0.5\norigin: [0, 0, 0]\n");
  EXPECT_THROW(load_ros_map(dir / "m.yaml"), core::Error);
}

// IMHuS's own elevator map (reference data in ../shared/external, read in place).
TEST(RosMap, LoadsTheImhusElevatorMap) {
  const OccupancyGrid grid = load_ros_map(std::filesystem::path(HRISIM_SHARED_DIR) / "external/imhus/elevator_map/elevator.yaml");
  EXPECT_EQ(grid.width(), 325);
  EXPECT_EQ(grid.height(), 325);
  EXPECT_DOUBLE_EQ(grid.resolution(), 0.075);
  EXPECT_TRUE(grid.origin().isApprox(Vec2(-12.0, -12.0)));
  std::size_t free = 0, occupied = 0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    free += grid.at(grid.cell_at(i)) == Cell::free;
    occupied += grid.at(grid.cell_at(i)) == Cell::occupied;
  }
  EXPECT_GT(free, 1000u);
  EXPECT_GT(occupied, 100u);
}

}  // namespace
}  // namespace hrisim::world
