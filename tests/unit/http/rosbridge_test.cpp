// The rosbridge socket's pieces without a socket: ROS 2 type names, definitions and CDR written byte by
// byte (alignment from the end of the encapsulation header, strings with their NUL, sequences with
// their count, fixed arrays without), messages checked and completed, the publish op in JSON, CBOR and
// cbor-raw, and the messages and topics of a session of the bundled elevator.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.hpp"
#include "http/ros_messages.hpp"
#include "http/ros_topics.hpp"
#include "http/rosbridge_graph.hpp"
#include "http/rosbridge_protocol.hpp"
#include "runs/event_json.hpp"
#include "scenario/load.hpp"
#include "sim/session.hpp"
#include "support/bytes.hpp"
#include "support/sessions.hpp"

namespace hrisim::http {
namespace {

using nlohmann::json;

using testing::elevator_session;
using testing::read_at;

/// The error message `work` throws as core::Error(bad_request), or a failure.
template <typename Work>
std::string bad_request_of(Work work) {
  try {
    work();
  } catch (const core::Error& e) {
    EXPECT_EQ(e.code(), core::ErrorCode::bad_request);
    return e.what();
  }
  ADD_FAILURE() << "no error";
  return {};
}


TEST(RosMessages, TypeNamesInBothSpellings) {
  EXPECT_EQ(ros::canonical_type("sensor_msgs/LaserScan"), "sensor_msgs/msg/LaserScan");
  EXPECT_EQ(ros::canonical_type("sensor_msgs/msg/LaserScan"), "sensor_msgs/msg/LaserScan");
  EXPECT_EQ(ros::canonical_type("LaserScan"), "");
  EXPECT_EQ(ros::canonical_type("a/b/c/d"), "");
  EXPECT_TRUE(ros::known_type("geometry_msgs/Twist"));
  EXPECT_TRUE(ros::known_type("geometry_msgs/msg/Twist"));
  EXPECT_FALSE(ros::known_type("geometry_msgs/msg/Wrench"));
}

TEST(RosMessages, AFullDefinitionListsEveryTypeItUsesOnce) {
  const std::string text = ros::full_definition("nav_msgs/msg/Odometry");
  EXPECT_TRUE(text.starts_with("std_msgs/Header header\nstring child_frame_id\n")) << text;
  const std::string separator = "\n" + std::string(80, '=') + "\nMSG: ";
  for (const char* used : {"std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/PoseWithCovariance", "geometry_msgs/Pose", "geometry_msgs/Point",
                           "geometry_msgs/Quaternion", "geometry_msgs/TwistWithCovariance", "geometry_msgs/Twist", "geometry_msgs/Vector3"}) {
    const std::size_t at = text.find(separator + used + "\n");
    EXPECT_NE(at, std::string::npos) << used;
    EXPECT_EQ(text.find(separator + used + "\n", at + 1), std::string::npos) << used << " twice";
  }
  EXPECT_THROW(ros::full_definition("geometry_msgs/msg/Wrench"), core::Error);
}

TEST(RosMessages, CdrAlignsEachFieldToItsSizeFromTheEndOfTheHeader) {
  // A Log: a Time (int32, uint32), a uint8, then strings (each a uint32 length with its NUL, aligned
  // to 4), then a uint32.
  const std::string cdr = ros::encode_cdr("rcl_interfaces/Log", {{"stamp", {{"sec", 3}, {"nanosec", 500}}}, {"level", 20}, {"name", "ab"}, {"line", 7}});
  const std::string expected_header("\0\1\0\0", 4);
  EXPECT_EQ(cdr.substr(0, 4), expected_header);
  EXPECT_EQ(read_at<std::int32_t>(cdr, 4), 3);
  EXPECT_EQ(read_at<std::uint32_t>(cdr, 8), 500u);
  EXPECT_EQ(cdr[12], 20);
  EXPECT_EQ(read_at<std::uint32_t>(cdr, 16), 3u) << "aligned to 4 after the byte: 3 bytes of padding";
  EXPECT_EQ(cdr.substr(20, 3), std::string("ab\0", 3));
  EXPECT_EQ(read_at<std::uint32_t>(cdr, 24), 1u) << "msg: empty, its NUL alone";
  EXPECT_EQ(cdr[28], '\0');
  EXPECT_EQ(read_at<std::uint32_t>(cdr, 32), 1u) << "file";
  EXPECT_EQ(read_at<std::uint32_t>(cdr, 40), 1u) << "function";
  EXPECT_EQ(read_at<std::uint32_t>(cdr, 48), 7u) << "line";
  EXPECT_EQ(cdr.size(), 52u);
}

TEST(RosMessages, CdrWritesSequencesWithTheirCountAndFixedArraysWithout) {
  json odometry = {{"pose", {{"covariance", std::vector<double>(36, 0.5)}}}};
  const std::string cdr = ros::encode_cdr("nav_msgs/msg/Odometry", odometry);
  // Header: Time (8), frame_id "" (4 + 1), then child_frame_id "" (4 + 1) from 16 of the data, then
  // the pose's float64s aligned to 8: from 24 of the data, 28 of the bytes.
  EXPECT_EQ(read_at<std::uint32_t>(cdr, 12), 1u);
  EXPECT_EQ(read_at<std::uint32_t>(cdr, 20), 1u);
  EXPECT_EQ(read_at<double>(cdr, 28 + 6 * 8), 1.0) << "the quaternion's w defaults to 1";
  EXPECT_EQ(read_at<double>(cdr, 28 + 7 * 8), 0.5) << "the covariance right after the pose, no count";
  EXPECT_EQ(cdr.size(), 4 + 24 + 7 * 8 + 36 * 8 + 6 * 8 + 36 * 8u);

  const sim::LaserReading reading{"base_scan", 10, {}, 0.3, -1.0, 0.5, 0.05, 20.0, {1.0, std::numeric_limits<double>::infinity(), 2.5}};
  const std::string scan = ros::encode_cdr("sensor_msgs/msg/LaserScan", ros::laser_scan(reading, 0.01, "robot/base_scan"));
  const std::size_t ranges = scan.size() - 4 - 3 * 4;  // the ranges' count, then 3 float32s, then intensities' count (0)
  EXPECT_EQ(read_at<std::uint32_t>(scan, ranges - 4), 3u);
  EXPECT_EQ(read_at<float>(scan, ranges), 1.0f);
  EXPECT_TRUE(std::isinf(read_at<float>(scan, ranges + 4))) << "no return is +inf in CDR";
  EXPECT_EQ(read_at<std::uint32_t>(scan, scan.size() - 4), 0u);

  const std::string image = ros::encode_cdr("sensor_msgs/CompressedImage", ros::compressed_image("\xff\xd8", "jpeg", "map", 1.0));
  EXPECT_EQ(read_at<std::uint32_t>(image, image.size() - 6), 2u);
  EXPECT_EQ(image.substr(image.size() - 2), "\xff\xd8");
}

TEST(RosMessages, ConformFillsDefaultsAndNamesWhatIsWrong) {
  const json twist = ros::conform("geometry_msgs/Twist", {{"linear", {{"x", 0.5}}}});
  EXPECT_EQ(twist, json::parse(R"({"linear": {"x": 0.5, "y": 0.0, "z": 0.0}, "angular": {"x": 0.0, "y": 0.0, "z": 0.0}})"));
  EXPECT_EQ(bad_request_of([] { ros::conform("geometry_msgs/Twist", {{"linear", 1}}); }), "linear must be an object (geometry_msgs/Vector3)");
  EXPECT_EQ(bad_request_of([] { ros::conform("geometry_msgs/Twist", {{"angular", {{"z", "left"}}}}); }), "angular.z must be a number");
  EXPECT_EQ(bad_request_of([] { ros::conform("geometry_msgs/Twist", {{"speed", 1}}); }), "speed is not a field of geometry_msgs/msg/Twist");
  EXPECT_EQ(bad_request_of([] { ros::conform("rcl_interfaces/Log", {{"level", 300}}); }), "level must be an integer from 0 to 255");
  EXPECT_EQ(bad_request_of([] { ros::conform("rcl_interfaces/Log", {{"line", -1}}); }), "line must be an integer from 0 to 4294967295");
  EXPECT_EQ(bad_request_of([] { ros::conform("rcl_interfaces/Log", {{"level", 2.5}}); }), "level must be an integer from 0 to 255");
  EXPECT_EQ(bad_request_of([] { ros::conform("rcl_interfaces/Log", {{"level", "20"}}); }), "level must be an integer from 0 to 255");
  EXPECT_EQ(bad_request_of([] { ros::conform("std_msgs/Header", {{"stamp", {{"sec", 2147483648.0}}}}); }), "stamp.sec must be an integer from -2147483648 to 2147483647");
  EXPECT_EQ(ros::conform("rcl_interfaces/Log", {{"level", 20.0}})["level"], 20) << "a whole float is the integer";
  EXPECT_EQ(ros::conform("visualization_msgs/Marker", {{"id", -7}})["id"], -7);
  EXPECT_EQ(bad_request_of([] { ros::conform("nav_msgs/Odometry", {{"pose", {{"covariance", {1, 2}}}}}); }), "pose.covariance must hold 36 items, not 2");
  EXPECT_EQ(bad_request_of([] { ros::conform("tf2_msgs/TFMessage", {{"transforms", {{{"child_frame_id", 3}}}}}); }), "transforms[0].child_frame_id must be a string");
  // uint8[] as rosbridge writes it in JSON (base64), as a list, or as bytes.
  const json two_bytes = json::binary({0, 1});
  EXPECT_EQ(ros::conform("sensor_msgs/CompressedImage", {{"data", "AAE="}})["data"], two_bytes);
  EXPECT_EQ(ros::conform("sensor_msgs/CompressedImage", {{"data", {0, 1}}})["data"], two_bytes);
  EXPECT_EQ(bad_request_of([] { ros::conform("sensor_msgs/CompressedImage", {{"data", {0, 256}}}); }), "data[1] must be an integer from 0 to 255");
}

TEST(RosbridgeProtocol, PublishInJsonCborAndCborRaw) {
  const json clock = ros::clock(1.25);
  const Response text = rosbridge::publish("/clock", "rosgraph_msgs/msg/Clock", clock, rosbridge::Compression::none, 1.25);
  EXPECT_EQ(text.content_type, "application/json");
  EXPECT_EQ(json::parse(text.body), json::parse(R"({"op": "publish", "topic": "/clock", "msg": {"clock": {"sec": 1, "nanosec": 250000000}}})"));

  const Response cbor = rosbridge::publish("/clock", "rosgraph_msgs/msg/Clock", clock, rosbridge::Compression::cbor, 1.25);
  EXPECT_EQ(cbor.content_type, kBinaryContentType);
  EXPECT_EQ(json::from_cbor(cbor.body), json::parse(text.body));

  const Response raw = rosbridge::publish("/clock", "rosgraph_msgs/msg/Clock", clock, rosbridge::Compression::cbor_raw, 1.25);
  const json decoded = json::from_cbor(raw.body);
  EXPECT_EQ(decoded["op"], "publish");
  EXPECT_EQ(decoded["msg"]["secs"], 1);
  EXPECT_EQ(decoded["msg"]["nsecs"], 250000000);
  const auto& bytes = decoded["msg"]["bytes"].get_binary();
  EXPECT_EQ(std::string(bytes.begin(), bytes.end()), ros::encode_cdr("rosgraph_msgs/Clock", clock));

  // uint8[] in JSON text is base64, as rosbridge writes it.
  const json image = ros::compressed_image("\xff\xd8", "jpeg", "map", 0.0);
  EXPECT_EQ(json::parse(rosbridge::json_text(image))["data"], "/9g=");
  EXPECT_EQ(rosbridge::compression_named("cbor-raw"), rosbridge::Compression::cbor_raw);
  EXPECT_EQ(rosbridge::compression_named("png"), std::nullopt);
  EXPECT_EQ(rosbridge::status("error", "no", "a"), json::parse(R"({"op": "status", "level": "error", "msg": "no", "id": "a"})"));
}

TEST(RosbridgeGraph, TheElevatorsTopicsAndWhatRosapiSaysOfThem) {
  const auto session = elevator_session();
  const rosbridge::Graph graph = rosbridge::graph_of(*session);
  for (const char* topic : {"/clock", "/tf", "/tf_static", "/people_markers", "/people", "/robot/people", "/rosout", "/scan", "/robot/base_scan", "/odom", "/robot/odom",
                            "/camera/overview/compressed"}) {
    EXPECT_NE(graph.find(topic), nullptr) << topic;
  }
  EXPECT_EQ(graph.velocity_topics.at("/cmd_vel"), "robot");
  EXPECT_EQ(graph.velocity_topics.at("/robot/cmd_vel"), "robot");

  const json raw = *rosbridge::introspect(graph, "/rosapi/topics_and_raw_types", json::object());
  ASSERT_EQ(raw["topics"].size(), raw["typedefs_full_text"].size());
  for (std::size_t i = 0; i < raw["topics"].size(); ++i) EXPECT_EQ(raw["typedefs_full_text"][i], ros::full_definition(raw["types"][i])) << raw["topics"][i];
  EXPECT_EQ((*rosbridge::introspect(graph, "/rosapi/topic_type", {{"topic", "scan"}}))["type"], "sensor_msgs/msg/LaserScan");
  EXPECT_EQ((*rosbridge::introspect(graph, "/rosapi/topic_type", {{"topic", "/cmd_vel"}}))["type"], "geometry_msgs/msg/Twist");
  EXPECT_EQ((*rosbridge::introspect(graph, "/rosapi/node_details", {{"node", "/elsewhere"}}))["publishing"], json::array());
  EXPECT_EQ(bad_request_of([&] { rosbridge::introspect(graph, "/rosapi/service_type", json::object()); }), "service must be a string");
  EXPECT_EQ(rosbridge::introspect(graph, "/hrisim/reset", json::object()), std::nullopt) << "answered with the session";
  EXPECT_EQ(rosbridge::find_service("rosapi/get_time")->type, "rosapi_msgs/srv/GetTime");
}

TEST(RosTopics, TheElevatorsMessagesConformToTheirTypes) {
  const auto session = elevator_session();
  const sim::RobotRuntime* runtime = session->robot_runtime(session->agent_id("robot"));
  ASSERT_NE(runtime, nullptr);
  const json scan = ros::laser_scan(runtime->lasers.at(0).reading, session->model().dt, "robot/base_scan");
  EXPECT_EQ(ros::conform("sensor_msgs/msg/LaserScan", scan)["ranges"].size(), runtime->lasers.at(0).reading.ranges.size());
  const json odometry = ros::odometry(runtime->odometry_reading, session->model().dt, "robot");
  EXPECT_EQ(odometry["header"]["frame_id"], "robot/odom");
  ros::conform("nav_msgs/msg/Odometry", odometry);

  const json moving = ros::transforms(*session, false), fixed = ros::transforms(*session, true);
  ASSERT_EQ(moving["transforms"].size(), 1u);
  EXPECT_EQ(moving["transforms"][0]["header"]["frame_id"], "map");
  EXPECT_EQ(moving["transforms"][0]["child_frame_id"], "robot/base_link");
  EXPECT_EQ(moving["transforms"][0]["transform"]["translation"]["x"], runtime->robot.pose().x);
  EXPECT_GT(fixed["transforms"].size(), 1u);
  for (const json& transform : fixed["transforms"]) EXPECT_EQ(transform["header"]["frame_id"], "robot/base_link");
  ros::conform("tf2_msgs/msg/TFMessage", moving);

  const json markers = ros::people_markers(*session)["markers"];
  EXPECT_EQ(markers[0]["action"], 3) << "DELETEALL first: people who left are gone";
  ASSERT_GT(markers.size(), 1u);
  EXPECT_EQ(markers[1]["type"], 3) << "a cylinder";
  EXPECT_EQ(markers[2]["type"], 9) << "and their name";
  ros::conform("visualization_msgs/msg/MarkerArray", {{"markers", markers}});

  const json detected = ros::people_detected(*session, runtime->people);
  EXPECT_EQ(detected["people"].size(), runtime->people.people.size());
  for (const json& person : detected["people"]) EXPECT_EQ(person["tags"].size(), person["tagnames"].size());
  ros::conform("people_msgs/msg/People", detected);

  const json log = ros::log_line(runs::event_json(sim::Event{}));
  EXPECT_EQ(log["level"], 20);
  ros::conform("rcl_interfaces/msg/Log", log);
  EXPECT_EQ(ros::time_of(2.000000001), json::parse(R"({"sec": 2, "nanosec": 1})"));
}

}  // namespace
}  // namespace hrisim::http
