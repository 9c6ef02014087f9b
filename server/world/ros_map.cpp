#include "world/ros_map.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "core/files.hpp"

namespace hrisim::world {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, int line, const std::string& message) {
  nlohmann::json details{{"file", file.string()}};
  if (line > 0) details["line"] = line;
  throw core::Error(core::ErrorCode::bad_request,
                    file.string() + (line > 0 ? ":" + std::to_string(line) : "") + ": " + message, details);
}

std::string trim(std::string text) {
  const auto begin = text.find_first_not_of(" \t\r\"'");
  if (begin == std::string::npos) return "";
  const auto end = text.find_last_not_of(" \t\r\"'");
  return text.substr(begin, end - begin + 1);
}

double parse_number(const std::filesystem::path& file, int line, const std::string& key, const std::string& text) {
  double value = 0.0;
  const std::string trimmed = trim(text);
  const auto [end, ec] = std::from_chars(trimmed.data(), trimmed.data() + trimmed.size(), value);
  if (ec != std::errc() || end != trimmed.data() + trimmed.size()) {
    fail(file, line, key + ": expected a number, got '" + trimmed + "'");
  }
  return value;
}

/// A map's YAML is a dozen lines.
constexpr std::size_t kMaxMapYamlBytes = 64 * 1024;

std::string read_text(const std::filesystem::path& file, std::size_t max_bytes) {
  try {
    return core::read_file(file, max_bytes);
  } catch (const core::Error& e) {
    fail(file, 0, e.what());
  }
}

}  // namespace

RosMapInfo read_ros_map_yaml(const std::filesystem::path& yaml_file) {
  std::istringstream in(read_text(yaml_file, kMaxMapYamlBytes));
  RosMapInfo info;
  bool has_image = false, has_resolution = false, has_origin = false;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    if (const auto hash = text.find('#'); hash != std::string::npos) text.resize(hash);
    if (trim(text).empty()) continue;
    const auto colon = text.find(':');
    if (colon == std::string::npos) fail(yaml_file, line, "expected 'key: value'");
    const std::string key = trim(text.substr(0, colon));
    const std::string value = trim(text.substr(colon + 1));
    if (key == "image") {
      info.image = yaml_file.parent_path() / value;
      has_image = true;
    } else if (key == "resolution") {
      info.resolution = parse_number(yaml_file, line, key, value);
      if (!(info.resolution > 0.0)) fail(yaml_file, line, "resolution must be positive");
      has_resolution = true;
    } else if (key == "origin") {
      const auto open = value.find('['), close = value.find(']');
      if (open == std::string::npos || close == std::string::npos) fail(yaml_file, line, "origin: expected [x, y, yaw]");
      std::stringstream parts(value.substr(open + 1, close - open - 1));
      std::string part;
      double numbers[3];
      int count = 0;
      while (std::getline(parts, part, ',')) {
        if (count == 3) fail(yaml_file, line, "origin: expected exactly three numbers");
        numbers[count++] = parse_number(yaml_file, line, key, part);
      }
      if (count != 3) fail(yaml_file, line, "origin: expected exactly three numbers");
      if (numbers[2] != 0.0) fail(yaml_file, line, "origin: a rotated map (yaw != 0) is not supported");
      info.origin = {numbers[0], numbers[1], numbers[2]};
      has_origin = true;
    } else if (key == "negate") {
      info.negate = parse_number(yaml_file, line, key, value) != 0.0;
    } else if (key == "occupied_thresh") {
      info.occupied_thresh = parse_number(yaml_file, line, key, value);
    } else if (key == "free_thresh") {
      info.free_thresh = parse_number(yaml_file, line, key, value);
    } else if (key == "mode") {
      if (value != "trinary") fail(yaml_file, line, "mode: only 'trinary' is supported, got '" + value + "'");
    } else {
      fail(yaml_file, line, "unknown key '" + key + "'");
    }
  }
  if (!has_image) fail(yaml_file, 0, "missing key 'image'");
  if (!has_resolution) fail(yaml_file, 0, "missing key 'resolution'");
  if (!has_origin) fail(yaml_file, 0, "missing key 'origin'");
  if (!(info.free_thresh >= 0.0 && info.free_thresh < info.occupied_thresh && info.occupied_thresh <= 1.0)) {
    fail(yaml_file, 0, "thresholds must satisfy 0 <= free_thresh < occupied_thresh <= 1");
  }
  return info;
}

OccupancyGrid load_ros_map(const std::filesystem::path& yaml_file, const RosMapLimits& limits) {
  const RosMapInfo info = read_ros_map_yaml(yaml_file);
  if (limits.folder && !core::inside_folder(info.image, *limits.folder)) fail(yaml_file, 0, "image: no such file among the scenario files");
  std::istringstream in(read_text(info.image, core::kMaxScenarioFileBytes));
  // PGM header: magic, width, height, maxval, separated by white space and '#' comments.
  auto next_token = [&]() {
    std::string token;
    char c;
    while (in.get(c)) {
      if (c == '#') {
        std::string comment;
        std::getline(in, comment);
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        if (!token.empty()) return token;
      } else {
        token += c;
      }
    }
    return token;
  };
  const std::string magic = next_token();
  if (magic != "P5" && magic != "P2") fail(info.image, 0, "not a PGM image (magic '" + magic + "'); use P5 or P2");
  // A header number, or -1 for anything but a whole number below a million.
  auto next_number = [&]() {
    const std::string token = next_token();
    int value = -1;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    return ec == std::errc() && end == token.data() + token.size() && value < 1'000'000 ? value : -1;
  };
  const int width = next_number();
  const int height = next_number();
  const int max_value = next_number();
  if (width <= 0 || height <= 0 || max_value <= 0 || max_value > 255) {
    fail(info.image, 0, "unsupported PGM size or depth (8-bit grey images only)");
  }
  if (static_cast<std::int64_t>(width) * height > limits.max_cells) {
    fail(info.image, 0, std::to_string(width) + " × " + std::to_string(height) + " cells: more than the " + std::to_string(limits.max_cells) +
                            " a map may have (--max-grid-cells)");
  }
  std::vector<unsigned char> pixels(static_cast<std::size_t>(width) * height);
  if (magic == "P5") {
    in.read(reinterpret_cast<char*>(pixels.data()), static_cast<std::streamsize>(pixels.size()));
    if (in.gcount() != static_cast<std::streamsize>(pixels.size())) fail(info.image, 0, "image data is truncated");
  } else {
    for (auto& pixel : pixels) {
      const std::string token = next_token();
      if (token.empty()) fail(info.image, 0, "image data is truncated");
      pixel = static_cast<unsigned char>(std::clamp(std::atoi(token.c_str()), 0, max_value));
    }
  }

  OccupancyGrid grid(info.resolution, {info.origin.x, info.origin.y}, width, height);
  for (int row = 0; row < height; ++row) {
    for (int x = 0; x < width; ++x) {
      const double value = pixels[static_cast<std::size_t>(row) * width + x] / static_cast<double>(max_value);
      const double occupancy = info.negate ? value : 1.0 - value;
      const Cell cell = occupancy > info.occupied_thresh ? Cell::occupied
                        : occupancy < info.free_thresh  ? Cell::free
                                                        : Cell::unknown;
      grid.set({x, height - 1 - row}, cell);
    }
  }
  return grid;
}

}  // namespace hrisim::world
