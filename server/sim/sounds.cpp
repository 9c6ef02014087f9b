#include "sim/sounds.hpp"

#include <algorithm>
#include <cmath>

#include "core/random.hpp"

namespace hrisim::sim {
namespace {

using sensors::SoundSource;
using Vec3 = Eigen::Vector3d;

Vec3 at_height(const Vec2& point, double height) { return {point.x(), point.y(), height}; }

/// A seed for the `n`-th sound of something named: the same person, the same voice in every session.
std::uint64_t seed_of(std::string_view name, std::int64_t n) {
  return core::fnv1a(name) ^ (static_cast<std::uint64_t>(n) * 0x9E3779B97F4A7C15ULL);
}

void add_sound(State& state, SoundSource source, const Vec3& position, int speaker = -1) {
  source.position = position;
  state.sounds.push_back(std::move(source));
  state.speakers.push_back(speaker);
}

bool crosses(const Vec2& a, const Vec2& b, const std::vector<Vec2>& polygon) {
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    if (core::segments_cross(a, b, polygon[i], polygon[(i + 1) % polygon.size()])) return true;
  }
  return false;
}

/// Doors shutting and elevators arriving in this tick's events.
void sounds_of_events(const scenario::Model& model, State& state, std::size_t first_event, double now) {
  for (std::size_t e = first_event; e < state.events.size(); ++e) {
    const Event& event = state.events[e];
    if (const auto* door = event.as<events::DoorState>(); door && door->state == DoorPhase::closed) {
      const Vec2 middle = (model.doors[door->door].from + model.doors[door->door].to) / 2.0;
      add_sound(state, SoundSource::door(seed_of(event.subject, event.tick), now), at_height(middle, kDoorSoundHeight));
    } else if (const auto* arrived = event.as<events::ElevatorArrived>()) {
      const scenario::Door& door = model.doors[model.elevators[arrived->elevator].doors[arrived->floor]];
      add_sound(state, SoundSource::bell(now), at_height((door.from + door.to) / 2.0, kChimeHeight));
    }
  }
}

}  // namespace

void start_speaking(const scenario::Model& model, State& state, int agent, const scenario::Action& action) {
  // A robot running a routine with a `say` in it stays silent: robots' voices are not modelled.
  if (!model.heard || model.agents[agent].kind != scenario::AgentKind::human) return;
  const double now = static_cast<double>(state.tick) * model.dt;
  const std::string& id = model.agents[agent].id;
  SoundSource voice = action.target >= 0 ? SoundSource::clip(model.clips[action.target].second, now)
                                         : SoundSource::speech(core::fnv1a(id), seed_of(id, state.tick), now, action.value);
  add_sound(state, std::move(voice), at_height(state.agents[agent].position, kMouthHeight), agent);
}

void make_sounds(const scenario::Model& model, State& state, std::size_t first_event) {
  if (!model.heard) return;
  const double now = static_cast<double>(state.tick) * model.dt;
  // Dropped once they have passed the map's farthest corner.
  const double across = std::hypot(model.grid.width(), model.grid.height()) * model.grid.resolution();
  for (std::size_t s = state.sounds.size(); s-- > 0;) {
    if (state.sounds[s].end() + across / sensors::kSpeedOfSound >= now) continue;
    state.sounds.erase(state.sounds.begin() + static_cast<std::ptrdiff_t>(s));
    state.speakers.erase(state.speakers.begin() + static_cast<std::ptrdiff_t>(s));
  }
  for (std::size_t s = 0; s < state.sounds.size(); ++s) {
    if (state.speakers[s] >= 0) state.sounds[s].position = at_height(state.agents[state.speakers[s]].position, kMouthHeight);
  }
  std::vector<double> falls;
  for (std::size_t a = 0; a < state.agents.size(); ++a) {
    AgentState& person = state.agents[a];
    if (!person.active || model.agents[a].kind != scenario::AgentKind::human) continue;
    falls.clear();
    const double steps_before = person.animation.step_phase;
    sensors::footfalls(person.animation.step_phase, person.velocity.norm(), now, model.dt, falls);
    for (std::size_t k = 0; k < falls.size(); ++k) {
      const auto step = static_cast<std::int64_t>(std::floor(steps_before)) + static_cast<std::int64_t>(k);
      add_sound(state, SoundSource::footstep(seed_of(model.agents[a].id, step), falls[k]), at_height(person.position, 0.0));
    }
  }
  sounds_of_events(model, state, first_event, now);
}

int walls_between(const scenario::Model& model, const State& state, const Vec3& from, const Vec3& to) {
  const Vec2 a(from.x(), from.y()), b(to.x(), to.y());
  int walls = 0;
  if (model.map_from_image) {
    int edges = 0;
    for (const world::Segment& edge : model.outline) edges += core::segments_cross(a, b, edge.a, edge.b) ? 1 : 0;
    walls = (edges + 1) / 2;
  }
  for (const scenario::Obstacle& obstacle : model.obstacles) {
    if (obstacle.mesh.empty() && crosses(a, b, obstacle.polygon)) ++walls;
  }
  for (std::size_t d = 0; d < model.doors.size(); ++d) {
    if (state.doors[d].opening < 1.0 && core::segments_cross(a, b, model.doors[d].from, model.doors[d].to)) ++walls;
  }
  return walls;
}

void listen(const scenario::Model& model, State& state) {
  for (RobotRuntime& runtime : state.robots) {
    if (!runtime.hearing || !state.agents[runtime.agent].active) continue;
    RobotRuntime::Hearing& hearing = *runtime.hearing;
    const std::int64_t first = sensors::sample_index(static_cast<double>(state.tick - 1) * model.dt);
    const auto count = static_cast<int>(sensors::sample_index(static_cast<double>(state.tick) * model.dt) - first);
    const robots::RobotDescription& description = runtime.robot.description();
    sensors::MotorNoise motors;
    motors.position = at_height(runtime.robot.pose().position(), kMotorHeight);
    if (description.drive) {
      const robots::DifferentialDriveParams& drive = description.drive->params;
      const robots::Twist& twist = runtime.robot.twist();
      motors.load = std::min(1.0, std::abs(twist.linear) / drive.max_linear_speed + std::abs(twist.angular) / drive.max_angular_speed);
    }
    const sensors::WallCount walls = [&](const Vec3& source, const Vec3& listener) { return walls_between(model, state, source, listener); };
    hearing.microphones.record(state.sounds, walls, runtime.microphones_pose(), first, count, motors, hearing.random, hearing.block);
    hearing.history.add(hearing.block);
    if (due(hearing.direction_schedule, state.tick, model.dt)) {
      hearing.reading = hearing.direction.estimate(hearing.history.samples());
      hearing.reading_tick = state.tick;
    }
  }
}

}  // namespace hrisim::sim
