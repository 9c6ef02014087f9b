// Off-screen frames of boxes, capsules and cylinders: background, depth in metres, ids where the boxes are, and which way is
// left and up in the image.
#include "render/scene_renderer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace hrisim::render {
namespace {

Part box_at(double x, double y, double z, const Eigen::Vector3d& size, std::uint32_t id) {
  return Part::box(Eigen::Isometry3d(Eigen::Translation3d(x, y, z)), size, {0.8f, 0.2f, 0.1f}, id);
}

std::uint32_t id_at(const Frame& frame, const Camera& camera, int u, int v) { return frame.ids[static_cast<std::size_t>(v) * camera.width + u]; }
float depth_at(const Frame& frame, const Camera& camera, int u, int v) { return frame.depth[static_cast<std::size_t>(v) * camera.width + u]; }

TEST(SceneRenderer, AFrameWithNothingIsTheBackground) {
  SceneRenderer renderer(64, 48);
  Camera camera;
  camera.width = 64, camera.height = 48, camera.cx = 32, camera.cy = 24;
  const Frame frame = renderer.render({}, camera);
  ASSERT_EQ(frame.colour.width, 64);
  for (int v = 0; v < 48; v += 7) {
    for (int u = 0; u < 64; u += 9) {
      const std::uint8_t* p = frame.colour.pixel(u, v);
      EXPECT_NEAR(p[0], kBackground[0] * 255, 1);
      EXPECT_NEAR(p[2], kBackground[2] * 255, 1);
      EXPECT_EQ(id_at(frame, camera, u, v), 0u);
      EXPECT_EQ(depth_at(frame, camera, u, v), 0.0f);
    }
  }
}

TEST(SceneRenderer, AWallThreeMetresAheadIsThreeMetresDeepToTheCentimetre) {
  SceneRenderer renderer(256, 256);
  Camera camera;  // at the origin, looking along +x
  const Frame frame = renderer.render({box_at(3.05, 0, 0, {0.1, 40, 40}, 7)}, camera);
  for (int v = 0; v < 256; v += 15) {
    for (int u = 0; u < 256; u += 15) {
      EXPECT_NEAR(depth_at(frame, camera, u, v), 3.0, 0.01) << u << ", " << v;
      EXPECT_EQ(id_at(frame, camera, u, v), 7u);
    }
  }
}

TEST(SceneRenderer, DepthIsExactToFloatPrecisionNearAndFar) {
  // Depth is interpolated in metres, not taken back from a 24-bit window depth, whose steps grow
  // with the square of the distance (about 3 mm at 40 m with these near and far planes).
  SceneRenderer renderer(64, 64);
  Camera camera = Camera::pinhole(64, 64, 1.0, 0.05, 50.0);
  for (const double wall : {0.5, 7.25, 41.0}) {
    const Frame frame = renderer.render({box_at(wall + 0.05, 0, 0, {0.1, 200, 200}, 1)}, camera);
    for (int v = 0; v < 64; v += 9) {
      for (int u = 0; u < 64; u += 9) EXPECT_NEAR(depth_at(frame, camera, u, v), wall, wall * 1e-6) << wall << " m at " << u << ", " << v;
    }
  }
}

TEST(SceneRenderer, RenderIntoFillsTheCallersMemoryAsRenderDoesAndLeavesOutWhatIsNotAsked) {
  SceneRenderer renderer(64, 48);
  Camera camera = Camera::pinhole(64, 48, 1.2, 0.05, 50.0);
  camera.pose.translation() = Eigen::Vector3d(0, 0, 1.0);
  const Scene scene{box_at(2.2, 0.3, 1.1, {0.4, 0.4, 0.6}, 5), Part::capsule({3.0, -0.5, 0.2}, {3.0, -0.5, 1.6}, 0.2, {0.1f, 0.7f, 0.2f}, 6),
                    box_at(6.05, 0, 1, {0.1, 40, 40}, 9)};
  const Frame frame = renderer.render(scene, camera);
  const std::size_t pixels = 64 * 48;
  std::vector<std::uint8_t> colour(4 * pixels, 0xAB);
  std::vector<float> depth(pixels, -1.0f);
  std::vector<std::uint32_t> ids(pixels, 0xDEADBEEF);
  renderer.render_into(scene, camera, {colour.data(), depth.data(), nullptr});
  EXPECT_EQ(colour, frame.colour.pixels);
  EXPECT_EQ(depth, frame.depth);
  EXPECT_TRUE(std::all_of(ids.begin(), ids.end(), [](std::uint32_t id) { return id == 0xDEADBEEF; })) << "ids were not asked for";
  renderer.render_into(scene, camera, {nullptr, nullptr, ids.data()});
  EXPECT_EQ(ids, frame.ids);
  EXPECT_GT(std::count(ids.begin(), ids.end(), 5u), 0) << "the box is in view";
  EXPECT_GT(std::count(ids.begin(), ids.end(), 6u), 0) << "the capsule is in view";
}

TEST(SceneRenderer, LeftIsLeftAndUpIsUpAndTheNearerBoxHides) {
  SceneRenderer renderer(256, 256);
  Camera camera;
  camera.pose.translation() = Eigen::Vector3d(0, 0, 1.0);
  // A person-sized box ahead, one to the left, one above, and a wall behind them all.
  const Scene boxes{box_at(2.2, 0, 1.0, {0.4, 0.4, 0.4}, 1), box_at(2.2, 1.0, 1.0, {0.4, 0.4, 0.4}, 2),
                               box_at(2.2, 0, 1.8, {0.4, 0.4, 0.4}, 3), box_at(6.05, 0, 1, {0.1, 40, 40}, 9)};
  const Frame frame = renderer.render(boxes, camera);
  EXPECT_EQ(id_at(frame, camera, 128, 128), 1u);
  EXPECT_NEAR(depth_at(frame, camera, 128, 128), 2.0, 0.01) << "the near face of the box ahead";
  // (2.0, 1.0) projects to column cx − fx·y/x = 128 − 200·1/2 = 28; (2.0, up 0.8) to row 128 − 80 = 48.
  EXPECT_EQ(id_at(frame, camera, 28, 128), 2u);
  EXPECT_EQ(id_at(frame, camera, 228, 128), 9u) << "nothing on the right but the wall";
  EXPECT_EQ(id_at(frame, camera, 128, 48), 3u);
  EXPECT_EQ(id_at(frame, camera, 128, 208), 9u) << "nothing below but the wall";
  // Lit faces are the box's colour, darker or brighter, never the background.
  const std::uint8_t* p = frame.colour.pixel(128, 128);
  EXPECT_GT(p[0], p[1]);
}

TEST(SceneRenderer, ACapsuleIsRoundAndAsThickAsItsDiameter) {
  SceneRenderer renderer(256, 256);
  Camera camera;
  camera.pose.translation() = Eigen::Vector3d(0, 0, 1.0);
  // An upright capsule 0.2 m thick, 2 m ahead: 0.1 m to either side of the axis spans ±10 columns.
  const Frame frame = renderer.render({Part::capsule({2.1, 0, 0.5}, {2.1, 0, 1.5}, 0.1, {0.1f, 0.8f, 0.1f}, 4)}, camera);
  EXPECT_EQ(id_at(frame, camera, 128, 128), 4u);
  EXPECT_NEAR(depth_at(frame, camera, 128, 128), 2.0, 0.01) << "its surface towards the camera";
  EXPECT_EQ(id_at(frame, camera, 136, 128), 4u);
  EXPECT_EQ(id_at(frame, camera, 113, 128), 0u);
  EXPECT_EQ(id_at(frame, camera, 143, 128), 0u);
  // The top cap ends 0.1 m above the upper centre: row 128 − 200·0.6/2.1 ≈ 71.
  EXPECT_EQ(id_at(frame, camera, 128, 75), 4u);
  EXPECT_EQ(id_at(frame, camera, 128, 66), 0u);
}

TEST(SceneRenderer, PartsOutsideTheViewAreLeftOutButThoseReachingIntoItAreDrawn) {
  SceneRenderer renderer(128, 128);
  Camera camera;
  camera.width = camera.height = 128, camera.cx = camera.cy = 64, camera.fx = camera.fy = 64;  // 90° across
  // A long wall whose centre is far off to the left, out of view, but whose end reaches the middle;
  // a box behind the camera; a box beyond the far plane.
  Part wall = box_at(3.0, 20.0, 0.0, {0.1, 40.2, 4.0}, 3);
  const Frame frame = renderer.render({wall, box_at(-2, 0, 0, {1, 1, 1}, 4), box_at(60, 0, 0, {1, 1, 1}, 5)}, camera);
  EXPECT_EQ(id_at(frame, camera, 20, 64), 3u) << "the wall's end in the left half";
  EXPECT_EQ(id_at(frame, camera, 100, 64), 0u);
  for (const std::uint32_t id : frame.ids) EXPECT_TRUE(id == 0u || id == 3u);
}

TEST(SceneRenderer, AnOrthographicCameraLooksStraightDownWithDepthInMetres) {
  SceneRenderer renderer(200, 100);
  Camera camera;
  camera.width = 200, camera.height = 100;
  camera.orthographic_width = 20.0;  // 0.1 m per pixel
  camera.far = 100.0;
  camera.pose.translation() = Eigen::Vector3d(0, 0, 10);
  camera.pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();  // map x up the image
  Part cylinder = box_at(2.0, -5.0, 0.5, {1.0, 1.0, 1.0}, 5);
  cylinder.shape = Part::Shape::cylinder;
  const Frame frame = renderer.render({box_at(0, 0, -0.05, {40, 40, 0.1}, 1), cylinder}, camera);
  EXPECT_NEAR(depth_at(frame, camera, 10, 90), 10.0, 0.01) << "the floor";
  // Map (2, −5) is 2 m up from the centre (row 50 − 20) and 5 m to the right (column 100 + 50).
  EXPECT_EQ(id_at(frame, camera, 150, 30), 5u);
  EXPECT_NEAR(depth_at(frame, camera, 150, 30), 9.0, 0.01) << "the cylinder's top";
  EXPECT_EQ(id_at(frame, camera, 154, 30), 5u);
  EXPECT_EQ(id_at(frame, camera, 154, 26), 1u) << "round: the corner of its bounding square is floor";
}

}  // namespace
}  // namespace hrisim::render
