// Laser scans per second: hrisim's angular sweep (sensors::RayScene) and, for comparison, one Bullet
// rayTest per beam on the same scene (the design choice the robots issue asks to justify). Two
// scenes, 1081 beams (HSR's UST-20LX class laser, 270°, 20 m):
//   elevator — IMHuS's elevator map (its occupied cells' outline) and 6 people (two legs each);
//   open room — 30 m × 30 m, 50 boxes and 20 people.
// Both methods' ranges are compared beam by beam. Prints one line per scene and method: median of
// several repetitions.
//   usage: sensors_bench [repetitions=5] [path to shared/=../shared]
#include <algorithm>
#include <btBulletCollisionCommon.h>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "core/random.hpp"
#include "sensors/laser.hpp"
#include "world/outline.hpp"
#include "world/ros_map.hpp"

namespace {

using hrisim::core::Vec2;
using hrisim::sensors::Circle;
using hrisim::sensors::LaserParams;
using hrisim::world::Segment;
using Clock = std::chrono::steady_clock;

/// Leg radius and half the distance between the legs, m.
constexpr double kLegRadius = 0.07;
constexpr double kLegOffset = 0.1;

struct Scene {
  std::string name;
  std::vector<Segment> segments;
  std::vector<Circle> legs;
  std::vector<hrisim::core::Pose2> viewpoints;  ///< where the scanner stands, cycled through
};

void add_person(Scene& scene, const Vec2& at, double heading) {
  const Vec2 side(-std::sin(heading) * kLegOffset, std::cos(heading) * kLegOffset);
  scene.legs.push_back({at + side, kLegRadius});
  scene.legs.push_back({at - side, kLegRadius});
}

Scene open_room(hrisim::core::Random& random) {
  Scene scene{"open room, 50 boxes, 20 people", {}, {}, {}};
  // Four walls 0.1 m thick around the room (solids, as a scenario's walls are).
  hrisim::world::append_edges({{-0.1, -0.1}, {30.1, -0.1}, {30.1, 0}, {-0.1, 0}}, scene.segments);
  hrisim::world::append_edges({{-0.1, 30}, {30.1, 30}, {30.1, 30.1}, {-0.1, 30.1}}, scene.segments);
  hrisim::world::append_edges({{-0.1, 0}, {0, 0}, {0, 30}, {-0.1, 30}}, scene.segments);
  hrisim::world::append_edges({{30, 0}, {30.1, 0}, {30.1, 30}, {30, 30}}, scene.segments);
  for (int i = 0; i < 50; ++i) {
    const Vec2 centre(random.uniform(2, 28), random.uniform(2, 28));
    const double length = random.uniform(0.5, 1.0), width = random.uniform(0.5, 1.0), angle = random.uniform(0, 3.14);
    const Vec2 u(std::cos(angle) * length / 2, std::sin(angle) * length / 2), v(-std::sin(angle) * width / 2, std::cos(angle) * width / 2);
    hrisim::world::append_edges({centre - u - v, centre + u - v, centre + u + v, centre - u + v}, scene.segments);
  }
  for (int i = 0; i < 20; ++i) add_person(scene, {random.uniform(2, 28), random.uniform(2, 28)}, random.uniform(-3.14, 3.14));
  for (int i = 0; i < 16; ++i) scene.viewpoints.push_back({random.uniform(5, 25), random.uniform(5, 25), random.uniform(-3.14, 3.14)});
  return scene;
}

Scene elevator(const std::string& map, hrisim::core::Random& random) {
  const hrisim::world::OccupancyGrid grid = hrisim::world::load_ros_map(map);
  Scene scene{"elevator map, 6 people", hrisim::world::occupied_outline(grid), {}, {}};
  const hrisim::world::DistanceField field(grid);
  auto free_point = [&] {
    for (;;) {
      const Vec2 p(random.uniform(-10, 10), random.uniform(-10, 10));
      if (field.distance(grid, p) > 1.0) return p;
    }
  };
  for (int i = 0; i < 6; ++i) add_person(scene, free_point(), random.uniform(-3.14, 3.14));
  for (int i = 0; i < 16; ++i) {
    const Vec2 p = free_point();
    scene.viewpoints.push_back({p.x(), p.y(), random.uniform(-3.14, 3.14)});
  }
  return scene;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

/// Scans per second of the angular sweep; fills `ranges` with the scans of every viewpoint.
double sweep_rate(const Scene& scene, const LaserParams& params, int repetitions, std::vector<std::vector<double>>& ranges) {
  hrisim::sensors::RayScene rays(scene.segments);
  for (const Circle& leg : scene.legs) rays.add(leg);
  const hrisim::sensors::BeamFan fan(params.start_angle(), params.increment(), params.beams);
  ranges.assign(scene.viewpoints.size(), std::vector<double>(params.beams));
  std::vector<double> rates;
  for (int r = 0; r < repetitions; ++r) {
    const int scans = 2000;
    const auto start = Clock::now();
    for (int i = 0; i < scans; ++i) {
      const auto& at = scene.viewpoints[i % scene.viewpoints.size()];
      rays.scan(fan, at.position(), at.theta, params.max_range, ranges[i % scene.viewpoints.size()]);
    }
    rates.push_back(scans / std::chrono::duration<double>(Clock::now() - start).count());
  }
  return median(rates);
}

/// The same scene in a Bullet collision world: segments as 0.2 mm thin, 2 m tall boxes, legs as cylinders.
struct BulletScene {
  btDefaultCollisionConfiguration configuration;
  btCollisionDispatcher dispatcher{&configuration};
  btDbvtBroadphase broadphase;
  btCollisionWorld world{&dispatcher, &broadphase, &configuration};
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btCollisionObject>> objects;

  void add(std::unique_ptr<btCollisionShape> shape, const btTransform& pose) {
    shape->setMargin(0.0);  // Bullet's default 0.04 m margin would fatten every wall and leg
    auto object = std::make_unique<btCollisionObject>();
    object->setCollisionShape(shape.get());
    object->setWorldTransform(pose);
    world.addCollisionObject(object.get());
    shapes.push_back(std::move(shape));
    objects.push_back(std::move(object));
  }

  explicit BulletScene(const Scene& scene) {
    for (const Segment& segment : scene.segments) {
      const Vec2 middle = 0.5 * (segment.a + segment.b), along = segment.b - segment.a;
      btTransform pose(btQuaternion(btVector3(0, 0, 1), std::atan2(along.y(), along.x())), btVector3(middle.x(), middle.y(), 1.0));
      add(std::make_unique<btBoxShape>(btVector3(0.5 * along.norm(), 1e-4, 1.0)), pose);
    }
    for (const Circle& leg : scene.legs) {
      add(std::make_unique<btCylinderShapeZ>(btVector3(leg.radius, leg.radius, 0.45)),
          btTransform(btQuaternion::getIdentity(), btVector3(leg.centre.x(), leg.centre.y(), 0.45)));
    }
    world.updateAabbs();
  }
};

/// How far Bullet's ranges are from the sweep's, beam by beam.
struct Agreement {
  int beams = 0;
  int within_1mm = 0;
  int within_1cm = 0;
};

double bullet_rate(const Scene& scene, const LaserParams& params, int repetitions, const std::vector<std::vector<double>>& sweep,
                   Agreement& agreement) {
  BulletScene bullet(scene);
  const double height = 0.2;
  std::vector<double> rates;
  agreement = {};
  for (int r = 0; r < repetitions; ++r) {
    const int scans = 20;
    const auto start = Clock::now();
    for (int i = 0; i < scans; ++i) {
      const std::size_t view = i % scene.viewpoints.size();
      const auto& at = scene.viewpoints[view];
      for (int beam = 0; beam < params.beams; ++beam) {
        const double angle = at.theta + params.start_angle() + beam * params.increment();
        const btVector3 from(at.x, at.y, height);
        const btVector3 to = from + params.max_range * btVector3(std::cos(angle), std::sin(angle), 0);
        btCollisionWorld::ClosestRayResultCallback hit(from, to);
        bullet.world.rayTest(from, to, hit);
        const double range = hit.hasHit() ? hit.m_closestHitFraction * params.max_range : std::numeric_limits<double>::infinity();
        if (r == 0 && i < static_cast<int>(scene.viewpoints.size())) {
          const double other = sweep[view][beam];
          const double difference = std::isinf(range) && std::isinf(other) ? 0.0 : std::abs(range - other);
          ++agreement.beams;
          agreement.within_1mm += difference <= 1e-3;
          agreement.within_1cm += difference <= 1e-2;
        }
      }
    }
    rates.push_back(scans / std::chrono::duration<double>(Clock::now() - start).count());
  }
  return median(rates);
}

}  // namespace

int main(int argc, char** argv) {
  const int repetitions = argc > 1 ? std::atoi(argv[1]) : 5;
  const std::string shared = argc > 2 ? argv[2] : "../shared";
  const LaserParams params;  // 1081 beams over 270°, 20 m
  hrisim::core::Random random(7);
  std::vector<Scene> scenes{open_room(random)};
  const std::string map = std::filesystem::absolute(shared + "/external/imhus/elevator_map/elevator.yaml").string();
  if (std::filesystem::exists(map)) {
    scenes.push_back(elevator(map, random));
  } else {
    std::printf("elevator map not found at %s: skipping that scene\n", map.c_str());
  }
  std::printf("sensors_bench: %d beams over %.0f°, max range %.0f m, one thread, median of %d repetitions\n", params.beams,
              params.field_of_view * 180 / std::numbers::pi, params.max_range, repetitions);
  for (const Scene& scene : scenes) {
    std::vector<std::vector<double>> sweep;
    const double sweep_scans = sweep_rate(scene, params, repetitions, sweep);
    Agreement agreement;
    const double bullet_scans = bullet_rate(scene, params, repetitions, sweep, agreement);
    std::printf("%-32s %5zu segments %3zu legs: sweep %8.0f scans/s  bullet rayTest %6.1f scans/s (%.0fx); "
                "bullet's ranges within 1 mm of the sweep's: %.1f %%, within 1 cm: %.1f %%\n",
                scene.name.c_str(), scene.segments.size(), scene.legs.size(), sweep_scans, bullet_scans, sweep_scans / bullet_scans,
                100.0 * agreement.within_1mm / agreement.beams, 100.0 * agreement.within_1cm / agreement.beams);
  }
  return 0;
}
