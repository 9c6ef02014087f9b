#include "http/frames.hpp"

#include <cmath>
#include <map>
#include <memory>

#include "core/error.hpp"
#include "humans/skeleton.hpp"
#include "sim/session.hpp"

namespace hrisim::http {
namespace {

/// Walls drawn up to this height when the map gives none, m.
constexpr double kWallHeight = 2.5;
constexpr double kWallThickness = 0.05;
/// Off-screen contexts (one per image size) a rendering thread keeps at most.
constexpr std::size_t kRenderersPerThread = 4;
/// The overview camera's field of view across the image, rad.
constexpr double kOverviewFieldOfView = 1.0;

render::Box upright(const core::Vec2& at, double heading, const Eigen::Vector3d& size, std::array<float, 3> colour, std::uint32_t id) {
  render::Box box;
  box.pose.translation() = Eigen::Vector3d(at.x(), at.y(), size.z() / 2);
  box.pose.linear() = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  box.size = size;
  box.colour = colour;
  box.id = id;
  return box;
}

}  // namespace

std::vector<render::Box> scene_of(const sim::Session& session) {
  const scenario::Model& model = session.model();
  std::vector<render::Box> boxes;
  const world::OccupancyGrid& grid = model.grid;
  const double width = grid.width() * grid.resolution(), depth = grid.height() * grid.resolution();
  render::Box floor;
  floor.pose.translation() = Eigen::Vector3d(grid.origin().x() + width / 2, grid.origin().y() + depth / 2, -0.01);
  floor.size = Eigen::Vector3d(width, depth, 0.02);
  floor.colour = {0.92f, 0.92f, 0.9f};
  floor.id = 1;
  boxes.push_back(floor);
  for (const world::Segment& wall : model.outline) {
    const core::Vec2 along = wall.b - wall.a;
    const double height = std::isfinite(wall.top) ? wall.top : kWallHeight;
    boxes.push_back(upright((wall.a + wall.b) / 2, std::atan2(along.y(), along.x()), {along.norm(), kWallThickness, height}, {0.55f, 0.57f, 0.6f}, 2));
  }
  const sim::State& state = session.state();
  for (std::size_t a = 0; a < model.agents.size(); ++a) {
    const sim::AgentState& agent = state.agents[a];
    if (!agent.active) continue;
    const scenario::AgentDef& def = model.agents[a];
    const auto id = static_cast<std::uint32_t>(100 + a);
    if (def.kind == scenario::AgentKind::human) {
      const humans::BodyDimensions body = humans::body_dimensions(def.type).value_or(humans::kAdultBody);
      boxes.push_back(upright(agent.position, agent.heading, {0.6 * def.radius * 2, body.width, body.height}, {0.2f, 0.45f, 0.8f}, id));
    } else {
      const double height = def.robot_model ? def.robot_model->height : 1.0;
      boxes.push_back(upright(agent.position, agent.heading, {def.radius * 2, def.radius * 2, height}, {0.9f, 0.5f, 0.1f}, id));
    }
  }
  return boxes;
}

render::Camera overview_camera(const sim::Session& session, const std::string& name, int width, int height) {
  render::Camera camera;
  camera.width = width;
  camera.height = height;
  camera.cx = width / 2.0;
  camera.cy = height / 2.0;
  camera.fx = camera.fy = (width / 2.0) / std::tan(kOverviewFieldOfView / 2);
  camera.far = 500.0;
  const scenario::Model& model = session.model();
  if (name == "overview") {
    const world::OccupancyGrid& grid = model.grid;
    const double w = grid.width() * grid.resolution(), d = grid.height() * grid.resolution();
    // High enough that the whole map fits: its x along the image's height, y along the width.
    const double fit = std::max(d / 2 / (width / 2.0 / camera.fx), w / 2 / (height / 2.0 / camera.fy));
    camera.pose.translation() = Eigen::Vector3d(grid.origin().x() + w / 2, grid.origin().y() + d / 2, fit * 1.05 + kWallHeight);
    camera.pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();  // looking down, map x up
    return camera;
  }
  if (name == "follow") {
    for (std::size_t a = 0; a < model.agents.size(); ++a) {
      if (model.agents[a].kind != scenario::AgentKind::robot) continue;
      const sim::AgentState& robot = session.state().agents[a];
      const core::Vec2 behind = robot.position - 3.0 * core::heading_vector(robot.heading);
      camera.pose.translation() = Eigen::Vector3d(behind.x(), behind.y(), 2.5);
      camera.pose.linear() = (Eigen::AngleAxisd(robot.heading, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.45, Eigen::Vector3d::UnitY())).toRotationMatrix();
      return camera;
    }
    throw core::Error(core::ErrorCode::conflict, "the scenario has no robot to follow");
  }
  throw core::Error(core::ErrorCode::not_found, "no camera '" + name + "' (overview, follow)", {{"camera", name}});
}

render::Frame render_frame(const std::vector<render::Box>& boxes, const render::Camera& camera) {
  thread_local std::map<std::pair<int, int>, std::unique_ptr<render::BoxRenderer>> renderers;
  // A few sizes are kept; a client asking for ever new sizes does not pile up contexts.
  if (!renderers.contains({camera.width, camera.height}) && renderers.size() >= kRenderersPerThread) renderers.clear();
  auto& renderer = renderers[{camera.width, camera.height}];
  if (!renderer) renderer = std::make_unique<render::BoxRenderer>(camera.width, camera.height);
  return renderer->render(boxes, camera);
}

}  // namespace hrisim::http
