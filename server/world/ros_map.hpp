#pragma once
// Maps in ROS map_server's format (a YAML file naming a PGM/PNG image), as SLAM tools write them:
// resolution, origin [x, y, yaw], negate, occupied_thresh and free_thresh are honoured.
#include <filesystem>
#include <optional>
#include <string>

#include "world/occupancy_grid.hpp"

namespace hrisim::world {

struct RosMapInfo {
  std::filesystem::path image;  ///< resolved against the YAML file's folder
  double resolution = 0.0;
  core::Pose2 origin;           ///< lower-left pixel's pose; a non-zero yaw is refused (unused in practice)
  bool negate = false;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
};

/// What reading a map may touch and allocate.
struct RosMapLimits {
  std::optional<std::filesystem::path> folder;  ///< when set, the image must lie inside it as well
  std::int64_t max_cells = kDefaultMaxGridCells;
};

/// Reads the YAML part; throws core::Error naming the file, line and key on any problem.
RosMapInfo read_ros_map_yaml(const std::filesystem::path& yaml_file);

/// Loads the whole map (a map larger than limits.max_cells is refused before its pixels are read). Pixels are classified as map_server's trinary mode does: occupancy
/// p = (255 − v) / 255 (v / 255 with negate), occupied above occupied_thresh, free below
/// free_thresh, unknown between. Image row 0 is the top of the map.
OccupancyGrid load_ros_map(const std::filesystem::path& yaml_file, const RosMapLimits& limits = {});

}  // namespace hrisim::world
