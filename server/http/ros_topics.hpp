#pragma once
// A live session's state as ROS 2 messages in their JSON shape (the fields of ros_messages'
// definitions): the clock, a robot's laser scans and odometry, the transforms, the people as markers,
// events as log lines, camera images. Free of sockets: the rosbridge socket sends them.
#include <nlohmann/json.hpp>
#include <string>

namespace hrisim::sim {
class Session;
struct LaserReading;
struct OdometryReading;
struct PeopleReading;
}  // namespace hrisim::sim

namespace hrisim::http::ros {

/// Simulated time as builtin_interfaces/Time.
nlohmann::json time_of(double seconds);
/// rosgraph_msgs/msg/Clock.
nlohmann::json clock(double seconds);
/// sensor_msgs/msg/LaserScan in the laser's own frame; a beam with no return is +inf (REP 117), which
/// JSON text writes as null.
nlohmann::json laser_scan(const sim::LaserReading& reading, double dt, const std::string& frame);
/// nav_msgs/msg/Odometry: the pose the robot's wheel odometry believes, in ROBOT/odom (where it
/// started), and its measured twist in ROBOT/base_link.
nlohmann::json odometry(const sim::OdometryReading& reading, double dt, const std::string& robot);
/// The odometry frame of a robot: ROBOT/odom.
std::string odometry_frame(const std::string& robot);
/// tf2_msgs/msg/TFMessage: map → ROBOT/base_link for every robot, or (`sensors`) ROBOT/base_link →
/// ROBOT/SENSOR for every sensor.
nlohmann::json transforms(const sim::Session& session, bool sensors);
/// visualization_msgs/msg/MarkerArray: a DELETEALL, then every person in the scene as a cylinder with
/// their name above it.
nlohmann::json people_markers(const sim::Session& session);
/// people_msgs/msg/People: the people a robot's detector sees, in the map frame, by the names of
/// the people it tracks, with `face_visible` as a tag.
nlohmann::json people_detected(const sim::Session& session, const sim::PeopleReading& reading);
/// rcl_interfaces/msg/Log of an event (runs::event_json's shape): its subject as the name, its kind
/// and data as the text.
nlohmann::json log_line(const nlohmann::json& event);
/// sensor_msgs/msg/CompressedImage, its bytes held as JSON binary.
nlohmann::json compressed_image(const std::string& bytes, const std::string& format, const std::string& frame, double seconds);

}  // namespace hrisim::http::ros
