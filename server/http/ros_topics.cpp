#include "http/ros_topics.hpp"

#include <cmath>

#include "core/text.hpp"
#include "http/robot_frames.hpp"
#include "sim/session.hpp"

namespace hrisim::http::ros {
namespace {

using nlohmann::json;

// Marker's and Log's enumerations, by their values in their definitions.
constexpr int kCylinder = 3, kTextViewFacing = 9, kAdd = 0, kDeleteAll = 3;
constexpr int kLogInfo = 20;
/// How tall a person's marker stands, m.
constexpr double kPersonHeight = 1.7;

json header(double seconds, const std::string& frame) { return {{"stamp", time_of(seconds)}, {"frame_id", frame}}; }

json marker(double seconds, int id, int type, const Eigen::Isometry3d& where, const Eigen::Vector3d& scale) {
  return {{"header", header(seconds, kMapFrame)}, {"ns", "people"}, {"id", id}, {"type", type}, {"action", kAdd}, {"pose", pose(where)},
          {"scale", vector3(scale)}, {"color", {{"r", 0.9}, {"g", 0.5}, {"b", 0.1}, {"a", 1.0}}}};
}

}  // namespace

json time_of(double seconds) {
  const auto nanoseconds = static_cast<std::int64_t>(std::llround(std::max(0.0, seconds) * 1e9));
  return {{"sec", nanoseconds / 1'000'000'000}, {"nanosec", nanoseconds % 1'000'000'000}};
}

json clock(double seconds) { return {{"clock", time_of(seconds)}}; }

json laser_scan(const sim::LaserReading& reading, double dt, const std::string& frame) {
  const double last = reading.angle_min + reading.angle_increment * static_cast<double>(std::max<std::size_t>(reading.ranges.size(), 1) - 1);
  return {{"header", header(static_cast<double>(reading.tick) * dt, frame)},
          {"angle_min", reading.angle_min},
          {"angle_max", last},
          {"angle_increment", reading.angle_increment},
          {"range_min", reading.range_min},
          {"range_max", reading.range_max},
          {"ranges", reading.ranges}};
}

std::string odometry_frame(const std::string& robot) { return robot + "/odom"; }

json odometry(const sim::OdometryReading& reading, double dt, const std::string& robot) {
  return {{"header", header(static_cast<double>(std::max<std::int64_t>(reading.tick, 0)) * dt, odometry_frame(robot))},
          {"child_frame_id", base_frame(robot)},
          {"pose", {{"pose", pose(planar(reading.pose))}}},
          {"twist", {{"twist", {{"linear", {{"x", reading.twist.linear}}}, {"angular", {{"z", reading.twist.angular}}}}}}}};
}

json transforms(const sim::Session& session, bool sensors) {
  json list = json::array();
  for (const FrameTransform& frame : robot_frames(session)) {
    if (frame.sensor != sensors) continue;
    list.push_back({{"header", header(session.time(), frame.parent)}, {"child_frame_id", frame.child},
                    {"transform", {{"translation", vector3(frame.pose.translation())}, {"rotation", quaternion(Eigen::Quaterniond(frame.pose.linear()))}}}});
  }
  return {{"transforms", std::move(list)}};
}

json people_markers(const sim::Session& session) {
  const double seconds = session.time();
  json markers = json::array({{{"header", header(seconds, kMapFrame)}, {"ns", "people"}, {"action", kDeleteAll}}});
  const auto& agents = session.model().agents;
  for (std::size_t a = 0; a < agents.size(); ++a) {
    const sim::AgentState& state = session.state().agents[a];
    if (agents[a].kind != scenario::AgentKind::human || !state.active) continue;
    const int id = static_cast<int>(2 * a);
    const double diameter = 2.0 * agents[a].radius;
    markers.push_back(marker(seconds, id, kCylinder, planar({state.position.x(), state.position.y(), state.heading}, kPersonHeight / 2.0),
                             {diameter, diameter, kPersonHeight}));
    json name = marker(seconds, id + 1, kTextViewFacing, planar({state.position.x(), state.position.y(), 0.0}, kPersonHeight + 0.2), {0.0, 0.0, 0.25});
    name["text"] = agents[a].id;
    markers.push_back(std::move(name));
  }
  return {{"markers", std::move(markers)}};
}

json people_detected(const sim::Session& session, const sim::PeopleReading& reading) {
  json people = json::array();
  for (const sensors::Detection& person : reading.people) {
    people.push_back({{"name", session.model().agents.at(static_cast<std::size_t>(person.agent)).id},
                      {"position", {{"x", person.position.x()}, {"y", person.position.y()}}},
                      {"velocity", {{"x", person.velocity.x()}, {"y", person.velocity.y()}}},
                      {"reliability", 1.0},
                      {"tagnames", {"face_visible"}},
                      {"tags", {person.face_visible ? "true" : "false"}}});
  }
  return {{"header", header(static_cast<double>(std::max<std::int64_t>(reading.tick, 0)) * session.model().dt, kMapFrame)}, {"people", std::move(people)}};
}

json log_line(const json& event) {
  const std::string subject = event.value("subject", "");
  return {{"stamp", time_of(event.value("time", 0.0))},
          {"level", kLogInfo},
          {"name", subject.empty() ? "hrisim" : subject},
          {"msg", event.value("kind", "") + " " + core::json_text(event.value("data", json::object()))}};
}

json compressed_image(const std::string& bytes, const std::string& format, const std::string& frame, double seconds) {
  return {{"header", header(seconds, frame)}, {"format", format}, {"data", json::binary(std::vector<std::uint8_t>(bytes.begin(), bytes.end()))}};
}

}  // namespace hrisim::http::ros
