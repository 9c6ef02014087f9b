#pragma once
// Draws a scene of boxes (walls, furniture, people's and robots' parts until meshes exist) through a
// pinhole camera, off-screen: colour with simple lighting, depth in metres along the optical axis,
// and an instance id per pixel for segmentation. Reads a description of the scene, never the
// simulation itself.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "render/image.hpp"

namespace hrisim::render {

struct Box {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< centre and orientation in the map frame
  Eigen::Vector3d size = Eigen::Vector3d::Ones();           ///< edge lengths along its x, y, z, m
  std::array<float, 3> colour{0.7f, 0.7f, 0.7f};            ///< linear RGB, 0–1
  std::uint32_t id = 0;                                     ///< for segmentation; 0 is the background
};

/// A pinhole camera. Its frame follows REP 103 (x forward along the optical axis, y left, z up).
struct Camera {
  int width = 256, height = 256;
  double fx = 200.0, fy = 200.0;  ///< focal lengths, pixels
  double cx = 128.0, cy = 128.0;  ///< principal point, pixels from the top-left corner
  double near = 0.05, far = 50.0;  ///< m
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< in the map frame
};

struct Frame {
  ImageRgba8 colour;
  std::vector<float> depth;         ///< m along the optical axis, row 0 at the top; 0 where nothing is
  std::vector<std::uint32_t> ids;   ///< instance id per pixel, 0 for the background
};

/// Background colour of frames (a light grey-blue sky), linear RGB.
inline constexpr std::array<float, 3> kBackground{0.82f, 0.86f, 0.9f};

class BoxRenderer {
 public:
  /// An OSMesa context of the camera's size, its shaders and the unit cube; current on this thread.
  BoxRenderer(int width, int height);
  ~BoxRenderer();
  BoxRenderer(const BoxRenderer&) = delete;
  BoxRenderer& operator=(const BoxRenderer&) = delete;

  /// One frame of the boxes through the camera (whose size must be the renderer's).
  Frame render(const std::vector<Box>& boxes, const Camera& camera);

 private:
  struct Gl;
  std::unique_ptr<Gl> gl_;
};

}  // namespace hrisim::render
