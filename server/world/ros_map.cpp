#include "world/ros_map.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
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
      // In a grid of free, occupied and unknown cells, scale classifies as trinary does.
      if (value != "trinary" && value != "scale") fail(yaml_file, line, "mode: 'trinary' or 'scale' are supported, got '" + value + "'");
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

namespace {

/// A map image as grey levels, rows from the top.
struct GreyImage {
  int width = 0, height = 0;
  int max_value = 255;
  std::vector<unsigned char> pixels;
};

void check_size(const std::filesystem::path& image, std::int64_t width, std::int64_t height, std::int64_t max_cells) {
  // Each side first: a PNG header's 32-bit sides multiplied would overflow.
  if (width > max_cells || height > max_cells || width * height > max_cells) {
    fail(image, 0, std::to_string(width) + " × " + std::to_string(height) + " cells: more than the " + std::to_string(max_cells) +
                       " a map may have (--max-grid-cells)");
  }
}

/// A PNG (as HuNavSim's Isaac scenarios ship maps), decoded by OpenCV once its header's size is within
/// the limit (a small file may unpack into a huge image); colour channels are averaged, as map_server
/// does, and 16-bit levels brought to 8 bits; an alpha channel is not read.
GreyImage read_png(const std::filesystem::path& image, const std::string& bytes, std::int64_t max_cells) {
  if (bytes.size() < 24 || bytes.compare(12, 4, "IHDR") != 0) fail(image, 0, "not a PNG image (no IHDR header)");
  const auto big_endian = [&](std::size_t at) {
    return (std::int64_t{static_cast<unsigned char>(bytes[at])} << 24) | (std::int64_t{static_cast<unsigned char>(bytes[at + 1])} << 16) |
           (std::int64_t{static_cast<unsigned char>(bytes[at + 2])} << 8) | std::int64_t{static_cast<unsigned char>(bytes[at + 3])};
  };
  check_size(image, big_endian(16), big_endian(20), max_cells);
  const cv::Mat raw(1, static_cast<int>(bytes.size()), CV_8U, const_cast<char*>(bytes.data()));
  cv::Mat decoded = cv::imdecode(raw, cv::IMREAD_UNCHANGED);
  if (decoded.empty()) fail(image, 0, "the PNG image could not be decoded");
  if (decoded.depth() == CV_16U) decoded.convertTo(decoded, CV_8U, 1.0 / 257.0);
  if (decoded.depth() != CV_8U) fail(image, 0, "unsupported PNG depth (8 or 16 bits per channel)");
  GreyImage grey{decoded.cols, decoded.rows, 255, std::vector<unsigned char>(static_cast<std::size_t>(decoded.cols) * decoded.rows)};
  const int channels = decoded.channels();
  const int colours = channels >= 3 ? 3 : 1;  // grey (+ alpha) or BGR (+ alpha)
  for (int row = 0; row < decoded.rows; ++row) {
    const unsigned char* line = decoded.ptr<unsigned char>(row);
    for (int x = 0; x < decoded.cols; ++x) {
      int sum = 0;
      for (int c = 0; c < colours; ++c) sum += line[x * channels + c];
      grey.pixels[static_cast<std::size_t>(row) * decoded.cols + x] = static_cast<unsigned char>((sum + colours / 2) / colours);
    }
  }
  return grey;
}

/// A binary (P5) or ASCII (P2) PGM, as map_saver writes them.
GreyImage read_pgm(const std::filesystem::path& image, const std::string& bytes, std::int64_t max_cells) {
  std::istringstream in(bytes);
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
  if (magic != "P5" && magic != "P2") fail(image, 0, "not a PGM or PNG image (magic '" + magic + "'); use P5, P2 or PNG");
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
    fail(image, 0, "unsupported PGM size or depth (8-bit grey images only)");
  }
  check_size(image, width, height, max_cells);
  std::vector<unsigned char> pixels(static_cast<std::size_t>(width) * height);
  if (magic == "P5") {
    in.read(reinterpret_cast<char*>(pixels.data()), static_cast<std::streamsize>(pixels.size()));
    if (in.gcount() != static_cast<std::streamsize>(pixels.size())) fail(image, 0, "image data is truncated");
  } else {
    for (auto& pixel : pixels) {
      const std::string token = next_token();
      if (token.empty()) fail(image, 0, "image data is truncated");
      pixel = static_cast<unsigned char>(std::clamp(std::atoi(token.c_str()), 0, max_value));
    }
  }
  return {width, height, max_value, std::move(pixels)};
}

}  // namespace

OccupancyGrid load_ros_map(const std::filesystem::path& yaml_file, const RosMapLimits& limits) {
  const RosMapInfo info = read_ros_map_yaml(yaml_file);
  if (limits.folder && !core::inside_folder(info.image, *limits.folder)) fail(yaml_file, 0, "image: no such file among the scenario files");
  const std::string bytes = read_text(info.image, core::kMaxScenarioFileBytes);
  const GreyImage image = bytes.starts_with("\x89PNG") ? read_png(info.image, bytes, limits.max_cells) : read_pgm(info.image, bytes, limits.max_cells);
  const int width = image.width, height = image.height;
  OccupancyGrid grid(info.resolution, {info.origin.x, info.origin.y}, width, height);
  for (int row = 0; row < height; ++row) {
    for (int x = 0; x < width; ++x) {
      const double value = image.pixels[static_cast<std::size_t>(row) * width + x] / static_cast<double>(image.max_value);
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
