// Frames per second of the box renderer (OSMesa, llvmpipe, one thread): a 256×256 RGB-D camera (the
// HSR head's size) and a 640×480 overview, in a room of walls and furniture with six people made of
// boxes. Each frame is drawn twice (ids, then lit colour) and read back whole: colour, depth, ids.
//   usage: render_bench [seconds per case = 3]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "render/box_renderer.hpp"
#include "render/offscreen_context.hpp"

namespace {

using hrisim::render::Box;
using hrisim::render::Camera;

Box box(double x, double y, double z, double sx, double sy, double sz, std::uint32_t id) {
  Box b;
  b.pose.translation() = Eigen::Vector3d(x, y, z);
  b.size = Eigen::Vector3d(sx, sy, sz);
  b.id = id;
  return b;
}

std::vector<Box> room() {
  std::vector<Box> boxes;
  std::uint32_t id = 1;
  // A 12 × 8 m room: floor, four walls, and furniture along the walls.
  boxes.push_back(box(0, 0, -0.05, 12, 8, 0.1, id++));
  boxes.push_back(box(6, 0, 1.25, 0.1, 8, 2.5, id++));
  boxes.push_back(box(-6, 0, 1.25, 0.1, 8, 2.5, id++));
  boxes.push_back(box(0, 4, 1.25, 12, 0.1, 2.5, id++));
  boxes.push_back(box(0, -4, 1.25, 12, 0.1, 2.5, id++));
  for (int i = 0; i < 20; ++i) boxes.push_back(box(-5 + 0.5 * i, 3.5 - (i % 2) * 7, 0.4, 0.45, 0.45, 0.8, id++));
  // Six people: legs, torso and head each.
  for (int p = 0; p < 6; ++p) {
    const double x = 1.0 + 0.6 * p, y = -1.5 + 0.6 * p;
    boxes.push_back(box(x, y, 0.45, 0.25, 0.35, 0.9, id));
    boxes.push_back(box(x, y, 1.2, 0.25, 0.45, 0.6, id));
    boxes.push_back(box(x, y, 1.65, 0.2, 0.2, 0.25, id++));
  }
  return boxes;
}

double frames_per_second(int width, int height, double fx, double seconds) {
  hrisim::render::BoxRenderer renderer(width, height);
  Camera camera;
  camera.width = width, camera.height = height, camera.fx = camera.fy = fx, camera.cx = width / 2.0, camera.cy = height / 2.0;
  camera.pose.translation() = Eigen::Vector3d(-4, 0, 1.2);
  const std::vector<Box> boxes = room();
  int frames = 0;
  const auto start = std::chrono::steady_clock::now();
  double elapsed = 0.0;
  while (elapsed < seconds) {
    camera.pose.linear() = Eigen::AngleAxisd(0.01 * frames, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    renderer.render(boxes, camera);
    ++frames;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return frames / elapsed;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 3.0;
  const auto& gl = hrisim::render::probe_gl();
  std::printf("render_bench: %s, %s; %zu boxes; colour + depth + ids per frame\n", gl.renderer.c_str(), gl.version.c_str(), room().size());
  std::printf("256x256 RGB-D camera   %8.1f frames/s\n", frames_per_second(256, 256, 200, seconds));
  std::printf("640x480 overview       %8.1f frames/s\n", frames_per_second(640, 480, 400, seconds));
  return 0;
}
