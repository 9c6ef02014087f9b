#pragma once
// What a session looks like to a ROS 2 client of the rosbridge socket (docs/rosbridge.md): the topics
// hrisim publishes with their types, the topics it takes a robot's velocity on, its services, and
// rosapi's answers about them (topics, types, definitions, nodes, services), as one node, /hrisim.
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace hrisim::sim {
class Session;
}

namespace hrisim::http::rosbridge {

/// What a published topic carries.
enum class Feed { clock, transforms, static_transforms, laser, odometry, people, detections, log, camera };

struct Topic {
  std::string name, type;  ///< type as "pkg/msg/Type"
  Feed feed;
  std::string robot;   ///< laser, odometry, detections
  std::string source;  ///< the laser's sensor; the camera's name
};

/// The velocity message type taken on a robot's velocity topics.
inline constexpr const char* kTwist = "geometry_msgs/msg/Twist";
/// The node everything is published by.
inline constexpr const char* kNode = "/hrisim";

/// A session's topics: each robot's (ROBOT/LASER, ROBOT/odom, ROBOT/people, ROBOT/cmd_vel) and the
/// first robot's under the names ROS drivers use (/scan, /odom, /people, /cmd_vel), /tf, /tf_static,
/// /clock, /people_markers, /rosout, and a compressed image per camera.
struct Graph {
  std::vector<Topic> published;
  std::map<std::string, std::string> velocity_topics;  ///< topic → the robot it drives
  const Topic* find(const std::string& name) const;
};
Graph graph_of(const sim::Session& session);

/// A service hrisim answers: its name, type, and its request's fields in order (for a call whose args
/// are a list).
struct Service {
  std::string name, type;
  std::vector<std::string> request_fields;
};
const std::vector<Service>& services();
const Service* find_service(const std::string& name);

/// A topic's or service's name with its leading '/' (clients also write "rosapi/topics").
std::string absolute_name(const std::string& name);

/// rosapi's answer to a call about the graph (topics, topics_and_raw_types, nodes, node_details,
/// services, service_type, topic_type, get_ros_version), or nullopt for another service. Throws
/// core::Error(bad_request) for a request that is not the service's.
std::optional<nlohmann::json> introspect(const Graph& graph, const std::string& service, const nlohmann::json& request);

}  // namespace hrisim::http::rosbridge
