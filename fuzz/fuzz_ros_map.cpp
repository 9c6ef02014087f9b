// Fuzz target: ROS maps (map_server's YAML and its PGM image). The input is the YAML, a line
// "---PGM---", then the image's bytes; both are written to a scratch folder and loaded with the limits
// a server applies.
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string_view>
#include <unistd.h>

#include "core/error.hpp"
#include "world/ros_map.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path folder = [] {
    auto path = std::filesystem::temp_directory_path() / ("hrisim-fuzz-map-" + std::to_string(getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view kSeparator = "\n---PGM---\n";
  const auto split = input.find(kSeparator);
  const std::string_view yaml = input.substr(0, split);
  const std::string_view image = split == std::string_view::npos ? std::string_view() : input.substr(split + kSeparator.size());
  std::ofstream(folder / "map.yaml", std::ios::binary | std::ios::trunc).write(yaml.data(), static_cast<std::streamsize>(yaml.size()));
  std::ofstream(folder / "map.pgm", std::ios::binary | std::ios::trunc).write(image.data(), static_cast<std::streamsize>(image.size()));
  try {
    hrisim::world::load_ros_map(folder / "map.yaml", {folder, 1'000'000});
  } catch (const hrisim::core::Error&) {
  }
  return 0;
}
