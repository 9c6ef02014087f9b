#include "world/ros_map.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

#include "core/error.hpp"
#include "support/temp_dir.hpp"

namespace hrisim::world {
namespace {

// hrisim's own map fixtures (tests/fixtures/maps, written by make_maps.py there).
const std::filesystem::path kMaps = std::filesystem::path(HRISIM_SOURCE_DIR) / "tests/fixtures/maps";
// IMHuS's published elevator map (../shared/external/SOURCES.md), read in place when ../shared is beside
// the project.
const std::filesystem::path kElevatorMap = std::filesystem::path(HRISIM_SHARED_DIR) / "external/imhus/elevator_map/elevator.yaml";

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

// hrisim's own map in the shape SLAM tools and image editors leave (tests/fixtures/maps/lobby.yaml):
// binary P5 with a comment in its header, unknown grey around the scanned area, 255 beside 254, a YAML
// with trailing zeros and no final newline. It takes the paths IMHuS's elevator map takes.
TEST(RosMap, SlamStyleFixtureLoadsEveryCell) {
  const RosMapInfo info = read_ros_map_yaml(kMaps / "lobby.yaml");
  EXPECT_EQ(info.image.string(), (kMaps / "lobby.pgm").string());
  EXPECT_DOUBLE_EQ(info.resolution, 0.1) << "written 0.1000000";
  EXPECT_DOUBLE_EQ(info.origin.x, -3.0);
  EXPECT_DOUBLE_EQ(info.origin.y, -2.0);
  EXPECT_FALSE(info.negate);
  EXPECT_DOUBLE_EQ(info.free_thresh, 0.196) << "the last line, without a newline";
  const OccupancyGrid grid = load_ros_map(kMaps / "lobby.yaml");
  EXPECT_EQ(grid.width(), 60);
  EXPECT_EQ(grid.height(), 40);
  EXPECT_DOUBLE_EQ(grid.resolution(), 0.1);
  EXPECT_TRUE(grid.origin().isApprox(Vec2(-3.0, -2.0)));
  std::map<Cell, std::size_t> counts;
  for (std::size_t i = 0; i < grid.size(); ++i) ++counts[grid.at(grid.cell_at(i))];
  EXPECT_EQ(counts[Cell::free], 1775u);
  EXPECT_EQ(counts[Cell::occupied], 238u) << "the wall ring, the dividing wall, the table and two dark greys";
  EXPECT_EQ(counts[Cell::unknown], 387u) << "the unscanned border and three middle greys";
  EXPECT_EQ(grid.at({0, 0}), Cell::unknown) << "grey 205 outside the scan";
  EXPECT_EQ(grid.at({2, 2}), Cell::occupied) << "a corner of the wall ring";
  EXPECT_EQ(grid.at({30, 30}), Cell::occupied) << "the dividing wall";
  EXPECT_EQ(grid.at({30, 20}), Cell::free) << "its doorway";
  EXPECT_EQ(grid.at({6, 6}), Cell::free) << "pure white 255";
  EXPECT_EQ(grid.cell_of({1.65, 1.05}), (CellIndex{46, 30}));
  EXPECT_EQ(grid.at({46, 30}), Cell::occupied) << "the table";
}

// The same lobby as an RGB PNG with mode scale (HuNavSim's Isaac scenarios ship PNG maps): every cell
// as the PGM has it.
TEST(RosMap, PngMapsLoadAsTheirPgmTwin) {
  const OccupancyGrid pgm = load_ros_map(kMaps / "lobby.yaml");
  const OccupancyGrid png = load_ros_map(kMaps / "lobby_png.yaml");
  ASSERT_EQ(png.width(), pgm.width());
  ASSERT_EQ(png.height(), pgm.height());
  for (std::size_t i = 0; i < pgm.size(); ++i) ASSERT_EQ(png.at(png.cell_at(i)), pgm.at(pgm.cell_at(i))) << "cell " << i;
}

TEST(RosMap, APngLargerThanTheLimitIsRefusedBeforeDecoding) {
  testing::TempDir dir;
  std::string png = "\x89PNG\r\n\x1a\n";
  png += std::string("\x00\x00\x00\x0dIHDR", 8);
  png += std::string("\x00\x01\x00\x00\x00\x01\x00\x00\x08\x02\x00\x00\x00", 13);  // 65536 x 65536, then no data
  write(dir / "huge.png", png);
  write(dir / "m.yaml", "image: huge.png\nresolution: 0.05\norigin: [0, 0, 0]\n");
  try {
    load_ros_map(dir / "m.yaml");
    FAIL() << "a 65536 x 65536 map loaded";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("65536 × 65536 cells: more than the"), std::string::npos) << e.what();
  }
  write(dir / "m.yaml", "image: huge.png\nresolution: 0.05\norigin: [0, 0, 0]\nmode: raw\n");
  EXPECT_THROW(read_ros_map_yaml(dir / "m.yaml"), core::Error) << "raw is not read";

  // Sides whose product overflows 64 bits (fuzz_ros_map's finding): refused the same way.
  png.replace(16, 8, std::string("\xff\xff\xff\xff\xff\xff\xff\xff", 8));
  write(dir / "huge.png", png);
  write(dir / "m.yaml", "image: huge.png\nresolution: 0.05\norigin: [0, 0, 0]\n");
  try {
    load_ros_map(dir / "m.yaml");
    FAIL() << "a 4294967295 x 4294967295 map loaded";
  } catch (const core::Error& e) {
    EXPECT_NE(std::string(e.what()).find("4294967295 × 4294967295 cells: more than the"), std::string::npos) << e.what();
  }
}

// The fixture's image row 30 (map row 9) holds grey levels 89, 90, 205, 206, 253, 128, 1 at x = 10 to 16:
// occupancy (255 - v) / 255 is occupied above 0.65 (v <= 89) and free below 0.196 (v >= 206).
TEST(RosMap, SlamStyleFixtureGreysOnBothSidesOfTheThresholds) {
  const OccupancyGrid grid = load_ros_map(kMaps / "lobby.yaml");
  const std::vector<Cell> expected{Cell::occupied, Cell::unknown, Cell::unknown, Cell::free,
                                   Cell::free,     Cell::unknown, Cell::occupied};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(grid.at({10 + static_cast<int>(i), 9}), expected[i]) << "x = " << 10 + i;
  }
}

// An ASCII P2 image with maxval 15, negate 1 (dark is free), thresholds of its own, mode trinary, a quoted
// image name and comments (tests/fixtures/maps/negated_ascii.yaml).
TEST(RosMap, AsciiFixtureWithNegateAndItsOwnThresholds) {
  const RosMapInfo info = read_ros_map_yaml(kMaps / "negated_ascii.yaml");
  EXPECT_EQ(info.image.string(), (kMaps / "negated_ascii.pgm").string()) << "the quotes are not part of the name";
  EXPECT_TRUE(info.negate);
  EXPECT_DOUBLE_EQ(info.occupied_thresh, 0.7);
  EXPECT_DOUBLE_EQ(info.free_thresh, 0.3);
  const OccupancyGrid grid = load_ros_map(kMaps / "negated_ascii.yaml");
  ASSERT_EQ(grid.width(), 5);
  ASSERT_EQ(grid.height(), 3);
  EXPECT_DOUBLE_EQ(grid.resolution(), 0.5);
  EXPECT_TRUE(grid.origin().isApprox(Vec2(1.5, -0.5)));
  // Occupancy v / 15: 11 → 0.73 occupied, 10 → 0.67 unknown, 5 → 0.33 unknown, 4 → 0.27 free.
  const Cell o = Cell::occupied, f = Cell::free, u = Cell::unknown;
  const std::vector<std::vector<Cell>> image_rows{{o, o, o, u, f}, {u, f, u, u, f}, {f, f, f, o, o}};
  for (int row = 0; row < 3; ++row) {
    for (int x = 0; x < 5; ++x) {
      EXPECT_EQ(grid.at({x, 2 - row}), image_rows[static_cast<std::size_t>(row)][static_cast<std::size_t>(x)])
          << "image row " << row << ", x " << x;
    }
  }
  EXPECT_EQ(grid.cell_of({3.75, 0.75}), (CellIndex{4, 2}));
}

// IMHuS's own elevator map (reference data in ../shared/external, read in place).
TEST(RosMap, LoadsTheImhusElevatorMap) {
  if (!std::filesystem::exists(kElevatorMap)) {
    GTEST_SKIP() << "no ../shared/external/imhus/elevator_map beside the project: the project's own fixture "
                    "tests/fixtures/maps/lobby.yaml covers this path (RosMap.SlamStyleFixtureLoadsEveryCell)";
  }
  const OccupancyGrid grid = load_ros_map(kElevatorMap);
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
