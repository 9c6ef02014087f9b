// The Foxglove socket's pieces without a socket: the protocol's binary framing, both ways, and the
// messages built from a session of the bundled elevator (scene, transforms, laser, log), each as its
// advertised JSON Schema describes it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>

#include "core/error.hpp"
#include "core/json_schema.hpp"
#include "core/text.hpp"
#include "http/foxglove_messages.hpp"
#include "http/foxglove_protocol.hpp"
#include "runs/event_json.hpp"
#include "scenario/load.hpp"
#include "sim/camera_scene.hpp"
#include "sim/session.hpp"
#include "support/bytes.hpp"
#include "support/sessions.hpp"

namespace hrisim::http::foxglove {
namespace {

using nlohmann::json;

using testing::elevator_session;
using testing::read_at;


/// Whether `message` is what the schema hrisim advertises `schema_name` with allows.
void expect_described(const std::string& schema_name, const json& message) {
  const core::JsonSchema schema(json::parse(schema_text(schema_name)));
  for (const auto& error : schema.validate(message)) ADD_FAILURE() << schema_name << " " << error.pointer << ": " << error.message;
}

TEST(FoxgloveProtocol, ServerBinaryMessagesAreLittleEndianAfterTheirOpcode) {
  const std::string data = message_data(7, 1'500'000'000, "{}");
  ASSERT_EQ(data.size(), 15u);
  EXPECT_EQ(data[0], 1);
  EXPECT_EQ(read_at<std::uint32_t>(data, 1), 7u);
  EXPECT_EQ(read_at<std::uint64_t>(data, 5), 1'500'000'000u);
  EXPECT_EQ(data.substr(13), "{}");

  const std::string time = time_message(42);
  ASSERT_EQ(time.size(), 9u);
  EXPECT_EQ(time[0], 2);
  EXPECT_EQ(read_at<std::uint64_t>(time, 1), 42u);

  const std::string answer = service_call_response(3, 9, "json", "{\"tick\":1}");
  EXPECT_EQ(answer[0], 3);
  EXPECT_EQ(read_at<std::uint32_t>(answer, 1), 3u);
  EXPECT_EQ(read_at<std::uint32_t>(answer, 5), 9u);
  EXPECT_EQ(read_at<std::uint32_t>(answer, 9), 4u);
  EXPECT_EQ(answer.substr(13, 4), "json");
  EXPECT_EQ(answer.substr(17), "{\"tick\":1}");
}

TEST(FoxgloveProtocol, ClientBinaryMessagesAreReadOrRefusedSayingWhatIsMissing) {
  std::string publish("\x01\x05\x00\x00\x00{\"linear\":{}}", 18);
  EXPECT_EQ(opcode_of(publish), kClientMessageData);
  const ClientMessage message = read_client_message(publish);
  EXPECT_EQ(message.channel, 5u);
  EXPECT_EQ(message.payload, "{\"linear\":{}}");

  const std::string call = std::string("\x02\x01\x00\x00\x00\x0b\x00\x00\x00\x04\x00\x00\x00json{}", 19);
  const ServiceCall read = read_service_call(call);
  EXPECT_EQ(read.service, 1u);
  EXPECT_EQ(read.call, 11u);
  EXPECT_EQ(read.encoding, "json");
  EXPECT_EQ(read.payload, "{}");

  EXPECT_THROW(opcode_of(""), core::Error);
  const auto refusal = [](const std::function<void()>& read_it) {
    try {
      read_it();
    } catch (const core::Error& e) {
      return std::string(e.what());
    }
    return std::string("read");
  };
  EXPECT_NE(refusal([] { read_client_message(std::string("\x01\x05", 2)); }).find("channel id"), std::string::npos);
  EXPECT_NE(refusal([] { read_service_call(std::string("\x02\x01\x00\x00\x00\x0b\x00", 7)); }).find("call id"), std::string::npos);
  EXPECT_NE(refusal([] { read_service_call(std::string("\x02\x01\x00\x00\x00\x0b\x00\x00\x00\xff\x00\x00\x00js", 15)); }).find("255 bytes"),
            std::string::npos);
}

TEST(FoxgloveMessages, TimeIsWholeSecondsAndNanoseconds) {
  EXPECT_EQ(time_json(1.5), json({{"sec", 1}, {"nsec", 500'000'000}}));
  EXPECT_EQ(nanoseconds(2.25), 2'250'000'000u);
}

TEST(FoxgloveMessages, TheSceneIsItsFixedSolidsOnceAndWhatMovesWithTheRest) {
  const auto session = elevator_session();
  const render::Scene scene = sim::scene_of(*session);
  const json fixed = scene_update(scene, *session, true, 0.1), moving = scene_update(scene, *session, false, 0.1);
  expect_described("foxglove.SceneUpdate", fixed);
  expect_described("foxglove.SceneUpdate", moving);
  ASSERT_FALSE(fixed["entities"].empty());
  for (const json& entity : fixed["entities"]) {
    EXPECT_LT(std::stoul(entity["id"].get<std::string>()), sim::kDoorIdBase);
    EXPECT_EQ(entity["frame_id"], "map");
    EXPECT_EQ(entity["lifetime"], time_json(0.0)) << "kept for good";
  }
  for (const json& entity : moving["entities"]) EXPECT_EQ(entity["lifetime"], time_json(0.1)) << "gone unless sent again";
  // A person: one entity of their body's capsules, each a cylinder between its two end spheres.
  const auto capsule = std::find_if(scene.begin(), scene.end(), [](const render::Part& p) { return p.shape == render::Part::Shape::capsule; });
  ASSERT_NE(capsule, scene.end());
  const auto person = std::find_if(moving["entities"].begin(), moving["entities"].end(), [&](const json& e) { return e["id"] == std::to_string(capsule->id); });
  ASSERT_NE(person, moving["entities"].end());
  const auto capsules = std::count_if(scene.begin(), scene.end(), [&](const render::Part& p) { return p.id == capsule->id; });
  EXPECT_EQ((*person)["cylinders"].size(), static_cast<std::size_t>(capsules));
  EXPECT_EQ((*person)["spheres"].size(), 2u * static_cast<std::size_t>(capsules));
  const json& cylinder = (*person)["cylinders"][0];
  EXPECT_NEAR(cylinder["size"]["z"].get<double>(), (capsule->to - capsule->from).norm(), 1e-9);
  EXPECT_NEAR(cylinder["size"]["x"].get<double>(), 2.0 * capsule->radius, 1e-9);
  const json& q = cylinder["pose"]["orientation"];
  const Eigen::Vector3d axis = Eigen::Quaterniond(q["w"], q["x"], q["y"], q["z"]) * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(axis.dot((capsule->to - capsule->from).normalized()), 1.0, 1e-9) << "the cylinder lies along the capsule";
}

TEST(FoxgloveMessages, TransformsPutTheRobotOnTheMapAndItsSensorsOnIt) {
  const auto session = elevator_session();
  const json transforms = frame_transforms(*session);
  expect_described("foxglove.FrameTransforms", transforms);
  const sim::RobotRuntime* robot = session->robot_runtime(session->agent_id("robot"));
  ASSERT_NE(robot, nullptr);
  std::set<std::string> children;
  for (const json& t : transforms["transforms"]) {
    children.insert(t["child_frame_id"]);
    if (t["child_frame_id"] != "robot/base_link") continue;
    EXPECT_EQ(t["parent_frame_id"], "map");
    EXPECT_NEAR(t["translation"]["x"].get<double>(), robot->robot.pose().x, 1e-12);
    EXPECT_NEAR(t["translation"]["y"].get<double>(), robot->robot.pose().y, 1e-12);
  }
  EXPECT_TRUE(children.contains("robot/base_link"));
  for (const robots::Sensor& sensor : session->model().agents[session->index_of(session->agent_id("robot"))].robot_model->sensors) {
    EXPECT_TRUE(children.contains("robot/" + sensor.name)) << sensor.name;
  }
}

TEST(FoxgloveMessages, ALaserScanKeepsEveryBeamAndWritesNoReturnAsZero) {
  const auto session = elevator_session();
  sim::LaserReading reading = session->robot_runtime(session->agent_id("robot"))->lasers.at(0).reading;
  ASSERT_GE(reading.tick, 0);
  reading.ranges.back() = std::numeric_limits<double>::infinity();
  const json scan = laser_scan(reading, session->model().dt);
  expect_described("foxglove.LaserScan", scan);
  ASSERT_EQ(scan["ranges"].size(), reading.ranges.size());
  EXPECT_EQ(scan["ranges"].back(), 0.0);
  EXPECT_EQ(scan["ranges"][0], reading.ranges[0]);
  EXPECT_NEAR(scan["end_angle"].get<double>(), reading.angle_min + reading.angle_increment * static_cast<double>(reading.ranges.size() - 1), 1e-12);
  EXPECT_NEAR(scan["pose"]["position"]["z"].get<double>(), reading.height, 1e-12);
}

TEST(FoxgloveMessages, AnEventIsALogLineNamedByItsSubject) {
  const json line = log_line({{"tick", 3}, {"time", 0.05}, {"kind", "command"}, {"subject", "ada"}, {"data", {{"text", "wait 1"}}}});
  expect_described("foxglove.Log", line);
  EXPECT_EQ(line["name"], "ada");
  EXPECT_EQ(line["level"], 2);
  EXPECT_EQ(line["message"], "command {\"text\":\"wait 1\"}");
  EXPECT_EQ(line["timestamp"], time_json(0.05));
}

TEST(FoxgloveMessages, ImagesAreBase64InJsonAsTheirSchemaSays) {
  // (core::JsonSchema knows no contentEncoding: the contract test checks images against Foxglove's schema.)
  const json image = compressed_image(std::string("\xff\xd8\xff", 3), "jpeg", "robot/head_rgbd", 1.0);
  EXPECT_EQ(image["data"], "/9j/");
  EXPECT_EQ(image["format"], "jpeg");
  EXPECT_EQ(image["frame_id"], "robot/head_rgbd");
  EXPECT_EQ(json::parse(schema_text("foxglove.CompressedImage"))["properties"]["data"]["contentEncoding"], "base64");
  EXPECT_THROW(schema_text("foxglove.Nothing"), core::Error);
}

TEST(FoxgloveMessages, DepthIsARawImageOfLittleEndianFloats) {
  const json image = depth_image({0.0f, 1.5f, 2.0f, 0.25f, 3.0f, 4.0f}, 3, 2, "robot/head_rgbd", 2.0);
  EXPECT_EQ(image["encoding"], "32FC1");
  EXPECT_EQ(image["width"], 3);
  EXPECT_EQ(image["height"], 2);
  EXPECT_EQ(image["step"], 12);
  const std::string bytes = core::base64_decode(image["data"].get<std::string>()).value();
  ASSERT_EQ(bytes.size(), 24u);
  EXPECT_EQ(read_at<float>(bytes, 4), 1.5f);
  EXPECT_EQ(read_at<float>(bytes, 20), 4.0f);
}

}  // namespace
}  // namespace hrisim::http::foxglove
