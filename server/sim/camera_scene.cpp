#include "sim/camera_scene.hpp"

#include <cmath>
#include <numbers>

#include "core/error.hpp"
#include "core/text.hpp"
#include "render/mesh.hpp"
#include "robots/robot.hpp"
#include "sim/session.hpp"

namespace hrisim::sim {
namespace {

using Colour = std::array<float, 3>;

constexpr Colour kFloorColour{0.92f, 0.92f, 0.9f};
constexpr Colour kWallColour{0.62f, 0.64f, 0.68f};
constexpr Colour kFurnitureColour{0.62f, 0.45f, 0.3f};  // wood, and boxes without a mesh
/// Colours of meshes that are not wood.
constexpr std::array<std::pair<std::string_view, Colour>, 8> kMeshColours{{{"sofa", {0.35f, 0.42f, 0.55f}},
                                                                          {"armchair", {0.35f, 0.42f, 0.55f}},
                                                                          {"plant", {0.25f, 0.55f, 0.25f}},
                                                                          {"stove", {0.85f, 0.85f, 0.85f}},
                                                                          {"lamp", {0.95f, 0.9f, 0.75f}},
                                                                          {"cup", {0.95f, 0.95f, 0.95f}},
                                                                          {"glass", {0.75f, 0.85f, 0.9f}},
                                                                          {"shelf", {0.55f, 0.4f, 0.28f}}}};
constexpr Colour kDoorColour{0.45f, 0.3f, 0.2f};
constexpr Colour kObjectColour{0.9f, 0.85f, 0.2f};
constexpr Colour kSkinColour{0.87f, 0.68f, 0.55f};
constexpr Colour kTrousersColour{0.2f, 0.22f, 0.3f};
constexpr Colour kRobotBodyColour{0.88f, 0.88f, 0.9f};
constexpr Colour kRobotBaseColour{0.25f, 0.25f, 0.28f};
/// Shirts, one per person in turn, so people can be told apart.
constexpr std::array<Colour, 6> kShirtColours{{{0.2f, 0.45f, 0.8f}, {0.8f, 0.25f, 0.2f}, {0.25f, 0.6f, 0.3f},
                                               {0.85f, 0.6f, 0.15f}, {0.55f, 0.3f, 0.65f}, {0.2f, 0.6f, 0.65f}}};

Eigen::Isometry3d upright(double x, double y, double theta, double z) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(x, y, z);
  pose.linear() = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return pose;
}

/// A robot's or an object's collision shape as a part (the shape's centre and axis as robots::Shape has them).
render::Part part_of(const robots::Shape& shape, const Eigen::Isometry3d& pose, Colour colour, std::uint32_t id) {
  render::Part part = render::Part::box(pose, shape.size, colour, id);
  switch (shape.kind) {
    case robots::Shape::Kind::box:
      break;
    case robots::Shape::Kind::cylinder:
      part.shape = render::Part::Shape::cylinder;
      part.size = Eigen::Vector3d(2 * shape.radius, 2 * shape.radius, shape.length);
      break;
    case robots::Shape::Kind::sphere:
      part.shape = render::Part::Shape::sphere;
      part.size = Eigen::Vector3d::Constant(2 * shape.radius);
      break;
    case robots::Shape::Kind::capsule: {
      const Eigen::Vector3d half = pose.linear() * Eigen::Vector3d(0, 0, 0.5 * shape.length);
      part = render::Part::capsule(pose.translation() - half, pose.translation() + half, shape.radius, colour, id);
      break;
    }
  }
  return part;
}

/// Straight down onto the whole map with a margin: map x to the right in the image, y up.
render::Camera overview_camera(const scenario::Model& model, int image_width, int image_height) {
  const world::OccupancyGrid& grid = model.grid;
  const double width = grid.width() * grid.resolution(), depth = grid.height() * grid.resolution();
  render::Camera top;
  top.width = image_width;
  top.height = image_height;
  top.cx = image_width / 2.0;
  top.cy = image_height / 2.0;
  top.orthographic_width = 1.05 * std::max(width, depth * image_width / image_height);
  top.near = 0.1;
  top.far = 2 * kDrawnWallHeight + 10.0;
  top.pose.translation() = Eigen::Vector3d(grid.origin().x() + width / 2, grid.origin().y() + depth / 2, kDrawnWallHeight + 10.0);
  // Its optical axis (x) down, its left (y) towards map −x, its up (z) towards map +y.
  top.pose.linear() << 0, -1, 0,
                       0, 0, 1,
                       -1, 0, 0;
  return top;
}

bool is_camera(const robots::Sensor& sensor) { return sensor.type == "camera" || sensor.type == "rgbd_camera"; }

}  // namespace

render::Scene scene_of(const Session& session) {
  const scenario::Model& model = session.model();
  const State& state = session.state();
  render::Scene scene;
  const world::OccupancyGrid& grid = model.grid;
  const double width = grid.width() * grid.resolution(), depth = grid.height() * grid.resolution();
  scene.push_back(render::Part::box(upright(grid.origin().x() + width / 2, grid.origin().y() + depth / 2, 0.0, -0.01), {width, depth, 0.02},
                                    kFloorColour, kFloorId));
  if (model.map_from_image) {
    for (const world::Segment& wall : model.outline) {
      const core::Vec2 along = wall.b - wall.a, middle = 0.5 * (wall.a + wall.b);
      const double height = std::isfinite(wall.top) ? wall.top : kDrawnWallHeight;
      scene.push_back(render::Part::box(upright(middle.x(), middle.y(), std::atan2(along.y(), along.x()), height / 2),
                                        {along.norm(), 0.05, height}, kWallColour, kWallsId));
    }
  } else {
    for (std::size_t o = 0; o < model.obstacles.size(); ++o) {
      const scenario::Obstacle& obstacle = model.obstacles[o];
      const auto id = kObstacleIdBase + static_cast<std::uint32_t>(o);
      const Eigen::Isometry3d pose = upright(obstacle.frame.x, obstacle.frame.y, obstacle.frame.theta, obstacle.height / 2);
      const bool wall = obstacle.name.starts_with("wall ");
      render::Part part = render::Part::box(pose, {obstacle.length, obstacle.width, obstacle.height}, wall ? kWallColour : kFurnitureColour, id);
      if (const render::TriangleMesh* mesh = obstacle.mesh.empty() ? nullptr : render::builtin_mesh(obstacle.mesh)) {
        part.shape = render::Part::Shape::mesh;
        part.mesh = mesh;
        for (const auto& [name, colour] : kMeshColours) {
          if (name == obstacle.mesh) part.colour = colour;
        }
      }
      scene.push_back(part);
    }
  }
  for (std::size_t d = 0; d < model.doors.size(); ++d) {
    // The closed share of the leaf, from the door's first end (sliding doors).
    const scenario::Door& door = model.doors[d];
    const double closed = 1.0 - state.doors[d].opening;
    if (closed <= 0.0) continue;
    const core::Vec2 along = door.to - door.from, middle = door.from + 0.5 * closed * along;
    scene.push_back(render::Part::box(upright(middle.x(), middle.y(), std::atan2(along.y(), along.x()), kDoorHeight / 2),
                                      {closed * along.norm(), door.thickness, kDoorHeight}, kDoorColour, kDoorIdBase + static_cast<std::uint32_t>(d)));
  }
  for (std::size_t o = 0; o < model.objects.size(); ++o) {
    scene.push_back(part_of(model.objects[o].shape, session.object_pose(static_cast<int>(o)), kObjectColour, kObjectIdBase + static_cast<std::uint32_t>(o)));
  }
  for (const AgentId id : session.agent_ids()) {
    const int a = session.index_of(id);
    const AgentState& agent = state.agents[a];
    const scenario::AgentDef& def = model.agents[a];
    const auto agent_id = kAgentIdBase + static_cast<std::uint32_t>(a);
    if (def.kind == scenario::AgentKind::human) {
      const humans::BodyCapsules body = session.human_body(a);
      const Colour shirt = kShirtColours[static_cast<std::size_t>(a) % kShirtColours.size()];
      for (int p = 0; p < humans::kBodyPartCount; ++p) {
        using humans::BodyPart;
        const auto part = static_cast<BodyPart>(p);
        const Colour colour = part == BodyPart::head ? kSkinColour
                              : (part == BodyPart::l_thigh || part == BodyPart::r_thigh || part == BodyPart::l_shin || part == BodyPart::r_shin ||
                                 part == BodyPart::l_foot || part == BodyPart::r_foot)
                                  ? kTrousersColour
                                  : shirt;
        scene.push_back(render::Part::capsule(body[p].from, body[p].to, body[p].radius, colour, agent_id));
      }
    } else if (const RobotRuntime* runtime = session.robot_runtime(id)) {
      const auto poses = runtime->robot.link_poses();
      const auto& links = runtime->robot.description().links;
      for (std::size_t l = 0; l < links.size(); ++l) {
        if (!links[l].collision) continue;
        const Eigen::Isometry3d pose = poses[l] * runtime->robot.collision_origin(l);
        scene.push_back(part_of(*links[l].collision, pose, l <= 1 ? kRobotBaseColour : kRobotBodyColour,
                                kRobotLinkIdBase + static_cast<std::uint32_t>(a) * 1000 + static_cast<std::uint32_t>(l)));
      }
    } else {
      render::Part disc = render::Part::box(upright(agent.position.x(), agent.position.y(), agent.heading, kDiscRobotHeight / 2),
                                            {2 * def.radius, 2 * def.radius, kDiscRobotHeight}, kRobotBodyColour, agent_id);
      disc.shape = render::Part::Shape::cylinder;
      scene.push_back(disc);
    }
  }
  return scene;
}

render::Scene scene_for(const Session& session, const CameraInfo& camera) {
  render::Scene scene = scene_of(session);
  if (camera.mount_id != 0) std::erase_if(scene, [&](const render::Part& part) { return part.id == camera.mount_id; });
  return scene;
}

std::vector<CameraInfo> cameras_of(const Session& session) {
  std::vector<CameraInfo> cameras;
  const scenario::Model& model = session.model();
  cameras.push_back({"overview", "orthographic", overview_camera(model, kOverviewWidth, kOverviewHeight), 0.0});
  bool followed = false;
  for (const AgentId id : session.agent_ids()) {
    const int a = session.index_of(id);
    if (model.agents[a].kind != scenario::AgentKind::robot) continue;
    const AgentState& robot = session.state().agents[a];
    if (!followed) {
      followed = true;
      CameraInfo follow{"follow", "perspective", render::Camera::pinhole(kOverviewWidth, kOverviewHeight, kFollowFieldOfView, 0.05, 100.0), 0.0};
      const core::Vec2 behind = robot.position - kFollowDistance * core::heading_vector(robot.heading);
      follow.camera.pose.translation() = Eigen::Vector3d(behind.x(), behind.y(), kFollowHeight);
      follow.camera.pose.linear() = (Eigen::AngleAxisd(robot.heading, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(kFollowPitch, Eigen::Vector3d::UnitY())).toRotationMatrix();
      cameras.push_back(follow);
    }
    const RobotRuntime* runtime = session.robot_runtime(id);
    if (!runtime) continue;
    for (const robots::Sensor& sensor : runtime->robot.description().sensors) {
      if (!is_camera(sensor)) continue;
      const robots::CameraSettings& s = sensor.camera;
      CameraInfo info{model.agents[a].id + "." + sensor.name, sensor.type, render::Camera::pinhole(s.width, s.height, s.horizontal_fov, s.near, s.far), s.rate};
      info.camera.pose = runtime->robot.sensor_pose(sensor);
      const int link = runtime->robot.description().find_link(sensor.link);
      info.mount_id = kRobotLinkIdBase + static_cast<std::uint32_t>(a) * 1000 + static_cast<std::uint32_t>(link);
      cameras.push_back(info);
    }
  }
  return cameras;
}

CameraInfo camera_of(const Session& session, const std::string& name, int width, int height) {
  std::vector<CameraInfo> cameras = cameras_of(session);
  std::vector<std::string> names;
  for (CameraInfo& info : cameras) {
    names.push_back(info.name);
    if (info.name != name) continue;
    render::Camera& c = info.camera;
    // A size given alone scales the other with it.
    const double sx = width > 0 ? static_cast<double>(width) / c.width : height > 0 ? static_cast<double>(height) / c.height : 1.0;
    const double sy = height > 0 ? static_cast<double>(height) / c.height : sx;
    const int w = static_cast<int>(std::lround(c.width * sx)), h = static_cast<int>(std::lround(c.height * sy));
    if (c.orthographic_width > 0.0) {
      c = overview_camera(session.model(), w, h);
    } else {
      // The horizontal field of view is kept, with square pixels and the principal point centred.
      const Eigen::Isometry3d pose = c.pose;
      c = render::Camera::pinhole(w, h, 2.0 * std::atan(c.width / 2.0 / c.fx), c.near, c.far);
      c.pose = pose;
    }
    return info;
  }
  throw core::Error(core::ErrorCode::not_found, "no camera '" + name + "' (" + core::join(names) + ")", "camera", name);
}

}  // namespace hrisim::sim
