#pragma once
// Draws a scene — boxes, cylinders, spheres, capsules and furniture meshes — through a pinhole or an
// orthographic camera, off-screen: colour with simple lighting, depth in metres along the optical axis,
// and an instance id per pixel for segmentation. Reads a description of the scene, never the
// simulation itself. The whole scene goes to OpenGL as one vertex buffer: one draw call per pass, so
// a frame's cost hardly depends on how many parts it has.
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "render/image.hpp"

namespace hrisim::render {

struct TriangleMesh;

/// One solid thing in the scene.
struct Part {
  enum class Shape { box, cylinder, sphere, capsule, mesh };
  Shape shape = Shape::box;
  /// Centre and orientation in the map frame (box, cylinder, sphere, mesh). A cylinder's axis is its z.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  /// Extent along its x, y, z, m: a box's edges, a cylinder's or sphere's diameters and length, the
  /// box a mesh's bounds are stretched to fill.
  Eigen::Vector3d size = Eigen::Vector3d::Ones();
  /// A capsule: the centres of its end spheres in the map frame, and its radius.
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
  double radius = 0.0;
  const TriangleMesh* mesh = nullptr;  ///< Shape::mesh; must outlive the rendering
  std::array<float, 3> colour{0.7f, 0.7f, 0.7f};  ///< linear RGB, 0–1
  std::uint32_t id = 0;  ///< for segmentation (24 bits); 0 is the background

  static Part box(const Eigen::Isometry3d& pose, const Eigen::Vector3d& size, std::array<float, 3> colour, std::uint32_t id);
  static Part capsule(const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius, std::array<float, 3> colour, std::uint32_t id);
};

using Scene = std::vector<Part>;

/// A camera. Its frame follows REP 103 (x forward along the optical axis, y left, z up).
struct Camera {
  int width = 256, height = 256;
  double fx = 200.0, fy = 200.0;  ///< focal lengths, pixels (pinhole)
  double cx = 128.0, cy = 128.0;  ///< principal point, pixels from the top-left corner
  double near = 0.05, far = 50.0;  ///< m
  /// Orthographic when > 0: metres the image's width spans (square pixels); pinhole otherwise.
  double orthographic_width = 0.0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< in the map frame

  /// A pinhole camera with square pixels centred on the image, from its horizontal field of view (rad).
  static Camera pinhole(int width, int height, double horizontal_fov, double near, double far);
};

struct Frame {
  ImageRgba8 colour;
  std::vector<float> depth;         ///< m along the optical axis, row 0 at the top; 0 where nothing is
  std::vector<std::uint32_t> ids;   ///< instance id per pixel, 0 for the background
};

/// Where a frame's images are read back to: each width × height values, row-major from the top row;
/// an image whose pointer is null is not read back.
struct FrameTarget {
  std::uint8_t* colour = nullptr;  ///< RGBA8
  float* depth = nullptr;          ///< as Frame::depth
  std::uint32_t* ids = nullptr;
};

/// Background colour of frames (a light grey-blue sky), linear RGB.
inline constexpr std::array<float, 3> kBackground{0.82f, 0.86f, 0.9f};

class SceneRenderer {
 public:
  /// An OSMesa context of the camera's size and its shaders; current on this thread.
  SceneRenderer(int width, int height);
  ~SceneRenderer();
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;

  /// One frame of the scene through the camera (whose size must be the renderer's).
  Frame render(const Scene& scene, const Camera& camera);
  /// The same frame, read back straight into the caller's memory (a message being written, say), with
  /// no copy on the way.
  void render_into(const Scene& scene, const Camera& camera, const FrameTarget& target);

 private:
  struct Gl;
  std::unique_ptr<Gl> gl_;
  std::vector<float> vertices_;  ///< reused between frames
};

/// This thread's renderer of that size, kept per thread: at most a few sizes, so a client asking for
/// ever new sizes does not pile up contexts.
SceneRenderer& renderer_on_this_thread(int width, int height);

/// Renders on this thread with its renderer of the camera's size.
Frame render_on_this_thread(const Scene& scene, const Camera& camera);

}  // namespace hrisim::render
