#include "http/foxglove_messages.hpp"

#include <bit>
#include <cmath>
#include <map>

#include "core/error.hpp"
#include "core/text.hpp"
#include "sim/camera_scene.hpp"
#include "sim/session.hpp"

namespace hrisim::http::foxglove {
namespace {

using nlohmann::json;

// Foxglove's enumerations, by their values in its schemas.
constexpr int kLineStrip = 0;
constexpr int kLogInfo = 2;

json colour(const std::array<float, 3>& rgb, double alpha = 1.0) { return {{"r", rgb[0]}, {"g", rgb[1]}, {"b", rgb[2]}, {"a", alpha}}; }

/// An entity with every list of primitives present (empty), as Foxglove's panels read them; a lifetime
/// of 0 keeps it for good.
json empty_entity(const std::string& id, double time, double lifetime) {
  json entity = {{"timestamp", time_json(time)}, {"frame_id", kMapFrame}, {"id", id}, {"lifetime", time_json(lifetime)},
                 {"frame_locked", false}, {"metadata", json::array()}};
  for (const char* primitives : {"arrows", "cubes", "spheres", "cylinders", "lines", "triangles", "texts", "models"}) entity[primitives] = json::array();
  return entity;
}

/// A solid as Foxglove's primitives: a capsule is a cylinder between its end spheres; a mesh, the
/// box its bounds fill.
void add_part(json& entity, const render::Part& part) {
  if (part.shape == render::Part::Shape::capsule) {
    const Eigen::Vector3d axis = part.to - part.from;
    const Eigen::Quaterniond along = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis.norm() > 0.0 ? axis : Eigen::Vector3d::UnitZ());
    const double diameter = 2.0 * part.radius;
    entity["cylinders"].push_back({{"pose", pose((part.from + part.to) / 2.0, along)}, {"size", vector3({diameter, diameter, axis.norm()})},
                                   {"bottom_scale", 1.0}, {"top_scale", 1.0}, {"color", colour(part.colour)}});
    for (const Eigen::Vector3d& end : {part.from, part.to}) {
      entity["spheres"].push_back({{"pose", pose(end, Eigen::Quaterniond::Identity())}, {"size", vector3({diameter, diameter, diameter})},
                                   {"color", colour(part.colour)}});
    }
    return;
  }
  json solid = {{"pose", pose(part.pose)}, {"size", vector3(part.size)}, {"color", colour(part.colour)}};
  switch (part.shape) {
    case render::Part::Shape::cylinder:
      solid["bottom_scale"] = 1.0;
      solid["top_scale"] = 1.0;
      entity["cylinders"].push_back(std::move(solid));
      break;
    case render::Part::Shape::sphere:
      entity["spheres"].push_back(std::move(solid));
      break;
    default:
      entity["cubes"].push_back(std::move(solid));
  }
}

/// The path an agent walks, from where it stands through the points it has yet to reach, a little
/// above the floor.
void add_paths(json& entities, const sim::Session& session, double time, double lifetime) {
  constexpr double kPathHeight = 0.02;
  const auto& agents = session.state().agents;
  for (std::size_t a = 0; a < agents.size(); ++a) {
    const sim::Navigation& navigation = agents[a].navigation;
    if (!agents[a].active || !navigation.under_way || navigation.path_index >= navigation.path.size()) continue;
    json points = json::array({vector3({agents[a].position.x(), agents[a].position.y(), kPathHeight})});
    for (std::size_t p = navigation.path_index; p < navigation.path.size(); ++p) {
      points.push_back(vector3({navigation.path[p].x(), navigation.path[p].y(), kPathHeight}));
    }
    json entity = empty_entity("path/" + session.model().agents[a].id, time, lifetime);
    const bool robot = session.model().agents[a].kind == scenario::AgentKind::robot;
    entity["lines"].push_back({{"type", kLineStrip}, {"pose", pose(Eigen::Isometry3d::Identity())}, {"thickness", 0.03}, {"scale_invariant", false},
                               {"points", std::move(points)}, {"color", colour(robot ? std::array{0.1f, 0.4f, 0.9f} : std::array{0.9f, 0.5f, 0.1f}, 0.8)},
                               {"colors", json::array()}, {"indices", json::array()}});
    entities.push_back(std::move(entity));
  }
}

}  // namespace

std::uint64_t nanoseconds(double seconds) { return static_cast<std::uint64_t>(std::llround(std::max(0.0, seconds) * 1e9)); }

json time_json(double seconds) {
  const std::uint64_t ns = nanoseconds(seconds);
  return {{"sec", ns / 1'000'000'000u}, {"nsec", ns % 1'000'000'000u}};
}

json scene_update(const render::Scene& scene, const sim::Session& session, bool fixed, double lifetime) {
  const double time = session.time();
  lifetime = fixed ? 0.0 : lifetime;
  std::map<std::uint32_t, json> by_id;  // a person's capsules share their id: one entity
  for (const render::Part& part : scene) {
    if ((part.id < sim::kDoorIdBase) != fixed) continue;
    auto [entry, added] = by_id.try_emplace(part.id);
    if (added) entry->second = empty_entity(std::to_string(part.id), time, lifetime);
    add_part(entry->second, part);
  }
  json entities = json::array();
  for (auto& [id, entity] : by_id) entities.push_back(std::move(entity));
  if (!fixed) add_paths(entities, session, time, lifetime);
  return {{"deletions", json::array()}, {"entities", std::move(entities)}};
}

json frame_transforms(const sim::Session& session) {
  json transforms = json::array();
  for (const FrameTransform& frame : robot_frames(session)) {
    transforms.push_back({{"timestamp", time_json(session.time())}, {"parent_frame_id", frame.parent}, {"child_frame_id", frame.child},
                          {"translation", vector3(frame.pose.translation())}, {"rotation", quaternion(Eigen::Quaterniond(frame.pose.linear()))}});
  }
  return {{"transforms", std::move(transforms)}};
}

json laser_scan(const sim::LaserReading& reading, double dt) {
  json ranges = json::array();
  for (const double range : reading.ranges) ranges.push_back(std::isfinite(range) ? range : 0.0);
  const double last = reading.angle_min + reading.angle_increment * static_cast<double>(std::max<std::size_t>(reading.ranges.size(), 1) - 1);
  return {{"timestamp", time_json(static_cast<double>(reading.tick) * dt)}, {"frame_id", kMapFrame}, {"pose", pose(planar(reading.pose, reading.height))},
          {"start_angle", reading.angle_min}, {"end_angle", last}, {"ranges", std::move(ranges)}, {"intensities", json::array()}};
}

json people_poses(const sim::PeopleReading& reading, double dt) {
  json poses = json::array();
  for (const sensors::Detection& person : reading.people) {
    const double heading = person.velocity.norm() > 0.0 ? std::atan2(person.velocity.y(), person.velocity.x()) : 0.0;
    poses.push_back(pose(planar({person.position.x(), person.position.y(), heading}, sim::kPeopleDetectorHeight)));
  }
  return {{"timestamp", time_json(static_cast<double>(std::max<std::int64_t>(reading.tick, 0)) * dt)}, {"frame_id", kMapFrame}, {"poses", std::move(poses)}};
}

json compressed_image(const std::string& bytes, const std::string& format, const std::string& frame, double time) {
  return {{"timestamp", time_json(time)}, {"frame_id", frame}, {"data", core::base64_encode(bytes)}, {"format", format}};
}

json depth_image(const std::vector<float>& depth, int width, int height, const std::string& frame, double time) {
  static_assert(std::endian::native == std::endian::little, "32FC1 is little-endian");
  const std::string_view bytes(reinterpret_cast<const char*>(depth.data()), depth.size() * sizeof(float));
  return {{"timestamp", time_json(time)}, {"frame_id", frame}, {"width", width}, {"height", height}, {"encoding", "32FC1"},
          {"step", width * static_cast<int>(sizeof(float))}, {"data", core::base64_encode(bytes)}};
}

json log_line(const json& event) {
  const std::string subject = event.value("subject", "");
  return {{"timestamp", time_json(event.value("time", 0.0))},
          {"level", kLogInfo},
          {"message", event.value("kind", "") + " " + core::json_text(event.value("data", json::object()))},
          {"name", subject.empty() ? "hrisim" : subject},
          {"file", ""},
          {"line", 0}};
}

}  // namespace hrisim::http::foxglove
