// People's animated bodies in a session and what cameras see of them: the gait keeps planted feet
// still, motion primitives play, hold and blend out, and the head camera sees a person where she
// stands, pointing left and right as mirror images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "sim/camera_scene.hpp"
#include "sim/session.hpp"
#include "support/commands.hpp"
#include "support/scenarios.hpp"

namespace hrisim::sim {
namespace {

using humans::BodyPart;
using nlohmann::json;

humans::Capsule part(const humans::BodyCapsules& body, BodyPart which) { return body[static_cast<int>(which)]; }

std::shared_ptr<const scenario::Model> room_with(const json& humans, const json& steps, const json& robots = json::array()) {
  json extra = {{"humans", humans}, {"steps", steps}};
  if (!robots.empty()) extra["robots"] = robots;
  return testing::load_valid(testing::room_scenario(extra));
}

TEST(Animation, AWalkingPersonsPlantedFootDoesNotSlide) {
  Session session(room_with(json::array({{{"id", "ana"}, {"start", {{"x", 1}, {"y", 2}}}, {"preferred_speed", 1.2}}}),
                            json::parse(R"([{"name": "walk", "actions": [{"agent": "ana", "goto": {"pose": {"x": 9, "y": 2}}}]}])")),
                  1);
  const int ana = session.index_of(session.agent_id("ana"));
  // The gait's phase says which foot carries her: the left for the first half of each stride, the
  // right for the second. While she walks at full gait, that foot may not move.
  const humans::MotionClip& walk = *humans::builtin_motion("walk");
  const double stride = walk.speed() * walk.duration();
  double worst_slip = 0.0, walked = 0.0;
  int stances = 0, stance_foot = -1;
  Eigen::Vector2d planted = Eigen::Vector2d::Zero();
  while (session.time() < 7.0 && !session.state().finished) {
    session.tick();
    const AgentState& state = session.state().agents[ana];
    walked += state.velocity.norm() * session.model().dt;
    const double phase = state.animation.gait_distance / stride;
    const int foot = phase < 0.5 ? 0 : 1;
    const double into_stance = std::fmod(phase, 0.5) / 0.5;
    const bool steady = state.velocity.norm() >= humans::kFullGaitSpeed && std::abs(state.animation.turn_rate) < 0.1;
    if (!steady || into_stance < 0.05 || into_stance > 0.95) {
      stance_foot = -1;  // blending, turning, or the hand-over between feet
      continue;
    }
    const Eigen::Vector2d heel = part(session.human_body(ana), foot == 0 ? BodyPart::l_foot : BodyPart::r_foot).from.head<2>();
    if (foot != stance_foot) {
      stance_foot = foot;
      planted = heel;
      ++stances;
    }
    worst_slip = std::max(worst_slip, (heel - planted).norm());
  }
  EXPECT_GT(walked, 5.0) << "she walked";
  EXPECT_GE(stances, 6) << "step after step";
  EXPECT_LT(worst_slip, 0.03) << "m a planted heel moved while on the floor";
}

TEST(Animation, AMotionPlaysHoldsItsLastPoseAndBlendsOutOnceThePersonWalks) {
  Session session(room_with(json::array({{{"id", "ana"}, {"start", {{"x", 2}, {"y", 2}}}}}),
                            json::parse(R"([{"name": "point", "actions": [{"agent": "ana", "motion": {"name": "point_left", "duration": 2}}]},
                                            {"name": "wait", "actions": [{"agent": "ana", "wait": {"duration": 1}}]},
                                            {"name": "go", "actions": [{"agent": "ana", "goto": {"pose": {"x": 8, "y": 2}}}]}])")),
                  1);
  const int ana = session.index_of(session.agent_id("ana"));
  // Facing +x, her left is +y: how far her left hand reaches out to the side.
  const auto reach = [&] { return part(session.human_body(ana), BodyPart::l_forearm).to.y() - session.state().agents[ana].position.y(); };
  const double hanging = reach();
  EXPECT_LT(hanging, 0.3) << "the arm hangs at the start";
  while (session.time() < 1.5) session.tick();
  EXPECT_GT(reach(), 0.6) << "pointing to her left";
  EXPECT_EQ(session.state().agents[ana].animation.motion, humans::builtin_motion("point_left"));
  while (session.time() < 2.8) session.tick();
  EXPECT_GT(reach(), 0.6) << "still pointing after the primitive ended, while she stands";
  while (session.time() < 4.5) session.tick();
  EXPECT_GT(session.state().agents[ana].velocity.norm(), 0.5) << "walking";
  EXPECT_LT(reach(), 0.3) << "the arm swings by her side again";
  EXPECT_EQ(session.state().agents[ana].animation.motion, nullptr);

  // The same by command, and what a command may not say.
  testing::command(session, "ana", "motion wave 1.5");
  EXPECT_THROW(testing::command(session, "ana", "motion dance"), core::Error);
  EXPECT_THROW(testing::command(session, "ana", "motion wave -1"), core::Error);
  EXPECT_THROW(testing::command(session, "ana", "motion wave 2 3"), core::Error);
  session.tick();
  EXPECT_EQ(session.state().agents[ana].animation.motion, humans::builtin_motion("wave"));
}

TEST(Animation, AScenarioNamesOnlyShippedMotionsAndOnlyHumansPlayThem) {
  const auto errors_of = [](const json& actions) {
    const json scenario = testing::room_scenario({{"humans", json::array({{{"id", "ana"}, {"start", {{"x", 2}, {"y", 2}}}}})},
                                                  {"robots", json::array({{{"id", "bot"}, {"start", {{"x", 8}, {"y", 8}}}}})},
                                                  {"steps", json::array({{{"name", "s"}, {"actions", actions}}})}});
    const scenario::LoadResult result = scenario::load_scenario(scenario, {});
    EXPECT_FALSE(result.model);
    std::vector<std::string> pointers;
    for (const auto& error : result.errors) pointers.push_back(error.pointer);
    return pointers;
  };
  EXPECT_EQ(errors_of(json::parse(R"([{"agent": "ana", "motion": {"name": "dance"}}, {"agent": "bot", "motion": {"name": "wave"}}])")),
            (std::vector<std::string>{"/steps/0/actions/0/motion/name", "/steps/0/actions/1/agent"}));
  EXPECT_EQ(errors_of(json::parse(R"([{"agent": "ana", "motion": {"name": "wave", "duration": 0}}])")),
            (std::vector<std::string>{"/steps/0/actions/0/motion/duration"}));
}

/// Where a point of the map appears in a pinhole camera's image (column, row), and its depth.
Eigen::Vector3d project(const render::Camera& camera, const Eigen::Vector3d& point) {
  const Eigen::Vector3d p = camera.pose.inverse() * point;  // x forward, y left, z up
  return {camera.cx - camera.fx * p.y() / p.x(), camera.cy - camera.fy * p.z() / p.x(), p.x()};
}

json hsr_at_origin_of_room() {
  return json::array({{{"id", "hsr"}, {"model", "hsr"}, {"start", {{"x", 2}, {"y", 2}, {"theta", 0}}}, {"controller", {{"type", "idle"}}}}});
}

TEST(HeadCamera, APersonAheadIsInTheSegmentationWhereSheStandsAtHerDepth) {
  Session session(room_with(json::array({{{"id", "ana"}, {"start", {{"x", 4.2}, {"y", 2.3}, {"theta", 3.14159}}}}}),
                            json::parse(R"([{"name": "wait", "actions": [{"agent": "ana", "wait": {"duration": 5}}]}])"), hsr_at_origin_of_room()),
                  1);
  session.tick();
  const int ana = session.index_of(session.agent_id("ana"));
  const CameraInfo camera = camera_of(session, "hsr.head_rgbd", 256, 256);
  EXPECT_EQ(camera.camera.width, 256);
  EXPECT_NEAR(2.0 * std::atan(128.0 / camera.camera.fx), 1.047, 1e-6) << "the description's field of view";
  const render::Frame frame = render::render_on_this_thread(scene_for(session, camera), camera.camera);
  // Her chest: the torso's middle, on its surface facing the camera.
  const humans::Capsule torso = part(session.human_body(ana), BodyPart::torso);
  const Eigen::Vector3d chest = 0.5 * (torso.from + torso.to) - Eigen::Vector3d(torso.radius, 0, 0);
  const Eigen::Vector3d at = project(camera.camera, chest);
  ASSERT_GT(at.x(), 10);
  ASSERT_LT(at.x(), 246);
  ASSERT_GT(at.y(), 10);
  ASSERT_LT(at.y(), 246);
  const auto index = [&](double u, double v) { return static_cast<std::size_t>(std::lround(v)) * 256 + static_cast<std::size_t>(std::lround(u)); };
  EXPECT_EQ(frame.ids[index(at.x(), at.y())], kAgentIdBase + static_cast<std::uint32_t>(ana));
  EXPECT_NEAR(frame.depth[index(at.x(), at.y())], at.z(), 0.03) << "m along the optical axis to her chest";
  // A metre to her side is the room behind her.
  const Eigen::Vector3d beside = project(camera.camera, chest + Eigen::Vector3d(0, 1.0, 0));
  EXPECT_NE(frame.ids[index(std::clamp(beside.x(), 0.0, 255.0), beside.y())], kAgentIdBase + static_cast<std::uint32_t>(ana));
}

TEST(HeadCamera, PointingLeftAndPointingRightAreMirrorImages) {
  const auto mask = [](const std::string& motion) {
    // Right ahead of the camera (the HSR's head camera sits 2.2 cm left of the head's centre: she stands there too).
    Session session(room_with(json::array({{{"id", "ana"}, {"start", {{"x", 4.5}, {"y", 2.0}, {"theta", 3.14159265}}}}}),
                              json::array({{{"name", "point"}, {"actions", json::array({{{"agent", "ana"}, {"motion", {{"name", motion}}}}})}}}),
                              hsr_at_origin_of_room()),
                    1);
    while (session.time() < 1.2) session.tick();
    const CameraInfo camera = camera_of(session, "hsr.head_rgbd", 256, 256);
    const render::Frame frame = render::render_on_this_thread(scene_for(session, camera), camera.camera);
    // Mirrored about the column of her body's axis.
    const Vec2 at = session.state().agents[session.index_of(session.agent_id("ana"))].position;
    const double axis = project(camera.camera, Eigen::Vector3d(at.x(), at.y(), 1.0)).x();
    std::vector<bool> her(frame.ids.size());
    const std::uint32_t id = kAgentIdBase + static_cast<std::uint32_t>(session.index_of(session.agent_id("ana")));
    for (int v = 0; v < 256; ++v) {
      for (int u = 0; u < 256; ++u) {
        const int from = static_cast<int>(std::lround(u + axis - 127.5));
        her[v * 256 + u] = from >= 0 && from < 256 && frame.ids[v * 256 + from] == id;
      }
    }
    return her;
  };
  const std::vector<bool> left = mask("point_left"), right = mask("point_right");
  // Facing the robot, her left is the image's right: count her pixels on either side of her axis
  // (centred in the masks).
  int left_side = 0, right_side = 0, mirrored = 0, either = 0;
  for (int v = 0; v < 256; ++v) {
    for (int u = 0; u < 256; ++u) {
      const bool l = left[v * 256 + u];
      right_side += l && u > 128 + 25;
      left_side += l && u < 128 - 25;
      // Pointing right seen in a mirror is pointing left.
      const bool r_mirrored = right[v * 256 + (255 - u)];
      either += l || r_mirrored;
      mirrored += l && r_mirrored;
    }
  }
  EXPECT_GT(right_side, 5 * std::max(left_side, 1)) << "her left arm reaches out to the image's right";
  // Limbs are a few pixels wide, so half a pixel of rounding at the axis costs a good share.
  EXPECT_GT(static_cast<double>(mirrored) / either, 0.8) << "the two masks mirror each other (intersection over union)";
}

}  // namespace
}  // namespace hrisim::sim
