#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "sensors/odometry.hpp"
#include "sensors/people_detector.hpp"

namespace hrisim::sensors {
namespace {

constexpr double kDt = 1.0 / 60.0;

/// Root mean square position error over many seeds after driving `distance` straight at 0.5 m/s.
double rms_error(double distance, const OdometryParams& params) {
  double sum = 0.0;
  const int seeds = 300;
  for (int seed = 0; seed < seeds; ++seed) {
    Odometry odometry(params);
    core::Random random(static_cast<std::uint64_t>(seed));
    const int steps = static_cast<int>(std::lround(distance / 0.5 / kDt));
    for (int i = 0; i < steps; ++i) odometry.update({0.5, 0.0}, kDt, random);
    sum += (odometry.pose().position() - Vec2(distance, 0.0)).squaredNorm();
  }
  return std::sqrt(sum / seeds);
}

TEST(Odometry, DriftGrowsWithDistanceNotWithSteps) {
  const OdometryParams params;
  const double short_drive = rms_error(1.0, params), long_drive = rms_error(10.0, params);
  EXPECT_GT(short_drive, 0.0);
  EXPECT_GT(long_drive, 3.0 * short_drive) << "heading errors bend long drives: faster than √distance";
  // Along the path the error is the translation noise: 0.01 m per √m.
  OdometryParams along_only = params;
  along_only.heading_noise_per_metre = 0.0;
  EXPECT_NEAR(rms_error(4.0, along_only), 0.01 * 2.0, 0.003);
}

TEST(Odometry, ScaleErrorIsSystematic) {
  OdometryParams params;
  params.translation_noise = params.heading_noise_per_metre = params.heading_noise_per_radian = 0.0;
  params.scale_error = 0.02;
  Odometry odometry(params);
  core::Random random(1);
  for (int i = 0; i < 600; ++i) odometry.update({0.5, 0.0}, kDt, random);
  EXPECT_NEAR(odometry.pose().x, 5.0 * 1.02, 1e-9);
}

std::vector<Segment> wall_between() { return {{{3.0, 1.0}, {3.0, 3.0}}}; }

TEST(PeopleDetector, RespectsRangeFieldOfViewAndOcclusion) {
  PeopleDetectorParams params;
  params.miss_probability = 0.0;
  params.position_noise = params.velocity_noise = 0.0;
  const PeopleDetector detector(params);
  const auto wall = wall_between();
  RayScene scene(wall);
  const std::vector<PersonTruth> people{
      {0, {2.0, 0.0}, {0.5, 0.0}, 0.2},    // in front: seen
      {1, {4.0, 0.0}, {0.0, 0.0}, 0.2},    // right behind person 0: hidden
      {2, {5.0, 2.0}, {0.0, 0.0}, 0.2},    // behind the wall: hidden
      {3, {-3.0, 0.0}, {0.0, 0.0}, 0.2},   // behind the sensor, outside the 270° view: unseen
      {4, {0.0, 12.0}, {0.0, 0.0}, 0.2},   // beyond the 10 m range
      {5, {2.0, -2.0}, {0.0, 1.0}, 0.2}};  // to the right front: seen
  for (const PersonTruth& person : people) scene.add(Circle{person.position, person.radius});
  core::Random random(1);
  std::vector<Detection> detections;
  detector.detect(scene, {0.0, 0.0}, 0.0, people, random, detections);
  ASSERT_EQ(detections.size(), 2u);
  EXPECT_EQ(detections[0].agent, 0);
  EXPECT_NEAR(detections[0].range, 2.0, 1e-9);
  EXPECT_NEAR(detections[0].velocity.x(), 0.5, 1e-12);
  EXPECT_EQ(detections[1].agent, 5);
  EXPECT_NEAR(detections[1].bearing, -std::numbers::pi / 4, 1e-4);
}

TEST(PeopleDetector, MissesAndNoiseFollowTheParameters) {
  const PeopleDetector detector(PeopleDetectorParams{});  // 5 % misses, 0.05 m noise
  RayScene scene;
  const std::vector<PersonTruth> person{{0, {3.0, 1.0}, {0.0, 0.0}, 0.2}};
  scene.add(Circle{person[0].position, 0.2});
  core::Random random(9);
  std::vector<Detection> detections;
  int seen = 0;
  double sum_squares = 0.0;
  const int trials = 4000;
  for (int i = 0; i < trials; ++i) {
    detector.detect(scene, {0.0, 0.0}, 0.0, person, random, detections);
    if (detections.empty()) continue;
    ++seen;
    sum_squares += (detections[0].position - person[0].position).squaredNorm() / 2.0;
  }
  EXPECT_NEAR(1.0 - static_cast<double>(seen) / trials, 0.05, 0.012);
  EXPECT_NEAR(std::sqrt(sum_squares / seen), 0.05, 0.003);
}

TEST(PeopleDetector, AFaceIsVisibleWhenThePersonFacesTheSensorWithinRange) {
  PeopleDetectorParams params;
  params.miss_probability = 0.0;
  params.position_noise = params.velocity_noise = 0.0;
  const PeopleDetector detector(params);
  const double pi = std::numbers::pi;
  // Everyone on the sensor's x axis or near it; headings relative to facing the sensor (pi at x > 0).
  const std::vector<PersonTruth> people{
      {0, {2.0, 0.0}, {0.0, 0.0}, 0.2, pi},                     // facing the sensor
      {1, {2.0, 1.0}, {0.0, 0.0}, 0.2, pi},                     // looking past it, 26.6 degrees off: still frontal
      {2, {3.0, -1.5}, {0.0, 0.0}, 0.2, pi / 2},                // turned 63 degrees away: a profile
      {3, {-1.0, 2.5}, {0.0, 0.0}, 0.2, std::atan2(-2.5, 1.0)},  // facing the sensor, 2.7 m away
      {4, {0.0, -3.0}, {0.0, 0.0}, 0.2, -pi / 2},               // its back to the sensor
      {5, {4.0, -1.0}, {0.0, 0.0}, 0.2, std::atan2(1.0, -4.0)}};  // facing it, 4.1 m away: beyond the face range
  RayScene scene;
  for (const PersonTruth& person : people) scene.add(Circle{person.position, person.radius});
  core::Random random(1);
  std::vector<Detection> detections;
  detector.detect(scene, {0.0, 0.0}, 0.0, people, random, detections);
  std::map<int, bool> face;
  for (const Detection& detection : detections) face[detection.agent] = detection.face_visible;
  ASSERT_EQ(face.size(), 6u) << "every body is seen";
  EXPECT_TRUE(face[0]);
  EXPECT_TRUE(face[1]);
  EXPECT_FALSE(face[2]);
  EXPECT_TRUE(face[3]);
  EXPECT_FALSE(face[4]);
  EXPECT_FALSE(face[5]);
  EXPECT_DOUBLE_EQ(params.face_range, kFaceRange);
  EXPECT_DOUBLE_EQ(params.face_max_yaw, pi / 4);
}

}  // namespace
}  // namespace hrisim::sensors
