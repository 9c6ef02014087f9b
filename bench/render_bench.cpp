// Frames per second of the scene renderer (OSMesa, llvmpipe) on bundled scenarios: the HSR's head
// RGB-D camera at 256×256 (the gesture task's observation) and the 640×480 top-down overview, in the
// elevator scenario with six people and in the furnished apartment. Each frame is the whole path a
// client waits for: the scene taken from the session, drawn once into three colour images (lit
// colour, ids, depth in metres) and read back whole, as a WebSocket camera message is, into memory
// that is reused. The session steps between frames (not timed) so people move and gestures play.
//   usage: render_bench [seconds per case = 3]    (LP_NUM_THREADS=1 for one core)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "render/offscreen_context.hpp"
#include "render/scene_renderer.hpp"
#include "scenario/load.hpp"
#include "sim/camera_scene.hpp"
#include "sim/session.hpp"

namespace {

struct Figures {
  double frames_per_second = 0.0;
  double scene_ms = 0.0;  ///< taking the scene from the session, per frame
  std::size_t parts = 0;
};

Figures measure(const std::string& scenario, const std::string& camera_name, int width, int height, double seconds) {
  const auto loaded = hrisim::scenario::load_scenario_file(std::string(HRISIM_SOURCE_DIR) + "/scenarios/" + scenario + ".json");
  if (!loaded.model) {
    std::fprintf(stderr, "%s does not load\n", scenario.c_str());
    std::exit(2);
  }
  hrisim::sim::Session session(loaded.model, 1);
  for (int i = 0; i < 50; ++i) session.tick();  // people on their way
  Figures figures;
  int frames = 0;
  const std::size_t pixels = static_cast<std::size_t>(width) * height;
  std::vector<std::uint8_t> colour(4 * pixels);
  std::vector<float> depth(pixels);
  std::vector<std::uint32_t> ids(pixels);
  double scene_seconds = 0.0, elapsed = 0.0;
  while (elapsed < seconds) {
    session.tick();  // not timed: stepping is not rendering
    const auto before = std::chrono::steady_clock::now();
    const hrisim::sim::CameraInfo info = hrisim::sim::camera_of(session, camera_name, width, height);
    const hrisim::render::Scene scene = hrisim::sim::scene_for(session, info);
    const auto drawn = std::chrono::steady_clock::now();
    hrisim::render::renderer_on_this_thread(width, height).render_into(scene, info.camera, {colour.data(), depth.data(), ids.data()});
    const auto after = std::chrono::steady_clock::now();
    scene_seconds += std::chrono::duration<double>(drawn - before).count();
    elapsed += std::chrono::duration<double>(after - before).count();
    figures.parts = scene.size();
    ++frames;
  }
  figures.frames_per_second = frames / elapsed;
  figures.scene_ms = 1000.0 * scene_seconds / frames;
  return figures;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 3.0;
  const auto& gl = hrisim::render::probe_gl();
  std::printf("render_bench: %s, %s; colour + depth + ids per frame; LP_NUM_THREADS=%s\n", gl.renderer.c_str(), gl.version.c_str(),
              std::getenv("LP_NUM_THREADS") ? std::getenv("LP_NUM_THREADS") : "(unset)");
  for (const char* scenario : {"elevator", "apartment"}) {
    for (const auto& [camera, width, height] : {std::tuple{"robot.head_rgbd", 256, 256}, std::tuple{"overview", 640, 480}}) {
      const Figures f = measure(scenario, camera, width, height, seconds);
      std::printf("%-10s %-16s %4dx%-4d %8.1f frames/s  (%zu parts; scene from the session %.3f ms)\n", scenario, camera, width, height,
                  f.frames_per_second, f.parts, f.scene_ms);
    }
  }
  return 0;
}
