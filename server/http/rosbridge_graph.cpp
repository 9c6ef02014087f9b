#include "http/rosbridge_graph.hpp"

#include <algorithm>

#include "http/ros_messages.hpp"
#include "http/rosbridge_protocol.hpp"
#include "sim/camera_scene.hpp"
#include "sim/session.hpp"

namespace hrisim::http::rosbridge {
namespace {

using nlohmann::json;

/// A camera's name as a topic: ROS names take no '.', so ROBOT.SENSOR is ROBOT/SENSOR.
std::string camera_topic(std::string camera) {
  std::replace(camera.begin(), camera.end(), '.', '/');
  return "/camera/" + camera + "/compressed";
}

json topics_and_types(const Graph& graph, bool definitions) {
  json topics = json::array(), types = json::array(), texts = json::array();
  const auto add = [&](const std::string& name, const std::string& type) {
    topics.push_back(name);
    types.push_back(type);
    if (definitions) texts.push_back(ros::full_definition(type));
  };
  for (const Topic& topic : graph.published) add(topic.name, topic.type);
  for (const auto& [name, robot] : graph.velocity_topics) add(name, kTwist);
  json answer = {{"topics", topics}, {"types", types}};
  if (definitions) answer["typedefs_full_text"] = texts;
  return answer;
}

json node_details(const Graph& graph, const std::string& node) {
  json publishing = json::array(), subscribing = json::array(), served = json::array();
  if (absolute_name(node) == kNode) {
    for (const Topic& topic : graph.published) publishing.push_back(topic.name);
    for (const auto& [name, robot] : graph.velocity_topics) subscribing.push_back(name);
    for (const Service& service : services()) served.push_back(service.name);
  }
  return {{"subscribing", subscribing}, {"publishing", publishing}, {"services", served}};
}

}  // namespace

const Topic* Graph::find(const std::string& name) const {
  const auto found = std::find_if(published.begin(), published.end(), [&](const Topic& topic) { return topic.name == name; });
  return found == published.end() ? nullptr : &*found;
}

Graph graph_of(const sim::Session& session) {
  Graph graph;
  const auto add = [&](std::string name, const char* type, Feed feed, std::string robot = "", std::string source = "") {
    graph.published.push_back({std::move(name), type, feed, std::move(robot), std::move(source)});
  };
  add("/clock", "rosgraph_msgs/msg/Clock", Feed::clock);
  add("/tf", "tf2_msgs/msg/TFMessage", Feed::transforms);
  add("/tf_static", "tf2_msgs/msg/TFMessage", Feed::static_transforms);
  add("/people_markers", "visualization_msgs/msg/MarkerArray", Feed::people);
  add("/rosout", "rcl_interfaces/msg/Log", Feed::log);
  bool first_laser = true, first_odometry = true, first_detector = true, first_drive = true;
  const auto& agents = session.model().agents;
  for (std::size_t a = 0; a < agents.size(); ++a) {
    const sim::RobotRuntime* runtime = agents[a].kind == scenario::AgentKind::robot ? session.robot_runtime(session.agent_at(static_cast<int>(a))) : nullptr;
    if (!runtime) continue;
    const std::string& robot = agents[a].id;
    for (const auto& laser : runtime->lasers) {
      if (std::exchange(first_laser, false)) add("/scan", "sensor_msgs/msg/LaserScan", Feed::laser, robot, laser.mount->name);
      add("/" + robot + "/" + laser.mount->name, "sensor_msgs/msg/LaserScan", Feed::laser, robot, laser.mount->name);
    }
    if (std::exchange(first_odometry, false)) add("/odom", "nav_msgs/msg/Odometry", Feed::odometry, robot);
    add("/" + robot + "/odom", "nav_msgs/msg/Odometry", Feed::odometry, robot);
    if (runtime->people_detector) {
      if (std::exchange(first_detector, false)) add("/people", "people_msgs/msg/People", Feed::detections, robot);
      add("/" + robot + "/people", "people_msgs/msg/People", Feed::detections, robot);
    }
    if (agents[a].robot_model->drive) {
      if (std::exchange(first_drive, false)) graph.velocity_topics.emplace("/cmd_vel", robot);
      graph.velocity_topics.emplace("/" + robot + "/cmd_vel", robot);
    }
  }
  for (const sim::CameraInfo& camera : sim::cameras_of(session)) add(camera_topic(camera.name), "sensor_msgs/msg/CompressedImage", Feed::camera, "", camera.name);
  return graph;
}

const std::vector<Service>& services() {
  static const std::vector<Service> all = {
      {"/rosapi/topics", "rosapi_msgs/srv/Topics", {}},
      {"/rosapi/topics_and_raw_types", "rosapi_msgs/srv/TopicsAndRawTypes", {}},
      {"/rosapi/topic_type", "rosapi_msgs/srv/TopicType", {"topic"}},
      {"/rosapi/nodes", "rosapi_msgs/srv/Nodes", {}},
      {"/rosapi/node_details", "rosapi_msgs/srv/NodeDetails", {"node"}},
      {"/rosapi/services", "rosapi_msgs/srv/Services", {}},
      {"/rosapi/service_type", "rosapi_msgs/srv/ServiceType", {"service"}},
      {"/rosapi/get_ros_version", "rosapi_msgs/srv/GetROSVersion", {}},
      {"/rosapi/get_time", "rosapi_msgs/srv/GetTime", {}},
      {"/hrisim/reset", "std_srvs/srv/Trigger", {}},
      {"/hrisim/step", "hrisim_msgs/srv/Step", {"n"}},
      {"/hrisim/seek", "hrisim_msgs/srv/Seek", {"tick"}},
  };
  return all;
}

const Service* find_service(const std::string& name) {
  const auto found = std::find_if(services().begin(), services().end(), [&](const Service& service) { return service.name == absolute_name(name); });
  return found == services().end() ? nullptr : &*found;
}

std::string absolute_name(const std::string& name) { return name.starts_with('/') ? name : "/" + name; }

std::optional<json> introspect(const Graph& graph, const std::string& service, const json& request) {
  if (service == "/rosapi/topics") return topics_and_types(graph, false);
  if (service == "/rosapi/topics_and_raw_types") return topics_and_types(graph, true);
  if (service == "/rosapi/nodes") return json{{"nodes", {kNode}}};
  if (service == "/rosapi/node_details") return node_details(graph, string_field(request, "node"));
  if (service == "/rosapi/get_ros_version") return json{{"version", 2}, {"distro", "jazzy"}};
  if (service == "/rosapi/services") {
    json names = json::array();
    for (const Service& served : services()) names.push_back(served.name);
    return json{{"services", names}};
  }
  if (service == "/rosapi/service_type") {
    const Service* found = find_service(string_field(request, "service"));
    return json{{"type", found ? found->type : ""}};
  }
  if (service == "/rosapi/topic_type") {
    const std::string name = absolute_name(string_field(request, "topic"));
    const Topic* topic = graph.find(name);
    return json{{"type", topic ? topic->type : graph.velocity_topics.contains(name) ? kTwist : ""}};
  }
  return std::nullopt;
}

}  // namespace hrisim::http::rosbridge
