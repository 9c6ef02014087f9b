#include "humans/periodic_corridor.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/random.hpp"

namespace hrisim::humans {
namespace {

/// Weidmann's free speed, m/s; his γ, 1/m²; the density at which walking stops, people/m².
constexpr double kWeidmannFreeSpeed = 1.34;
constexpr double kWeidmannGamma = 1.913;
constexpr double kWeidmannJamDensity = 5.4;
/// Seyfried et al. 2005: the ring's length along its middle, m; the free speed of their walkers and its
/// spread, m/s; the space a walker takes standing, m (the a of d = a + b·v; b is kSeyfriedTimeGap).
constexpr double kSeyfriedRingLength = 17.3;
constexpr double kSeyfriedFreeSpeed = 1.24, kSeyfriedFreeSpeedSpread = 0.15;
constexpr double kSeyfriedStandingSpace = 0.36;
/// Wide enough for one RiMEA body (0.4 m) to sway, too narrow for two side by side.
constexpr double kSingleFileWidth = 0.7;
/// Free speeds are drawn within this many standard deviations of the mean (none walks backwards).
constexpr double kSpeedSpreadLimit = 2.0;

/// People near one end are seen again beyond the other: each is copied this far past the ends, m.
double ghost_reach(const CrowdParams& params, const PeriodicCorridor& corridor) {
  return std::max({params.orca.neighbour_distance, params.social_force.neighbour_distance, params.headway.horizon}) +
         2.0 * corridor.radius + params.personal_space.from_people;
}

std::vector<CrowdAgent> lattice(const PeriodicCorridor& corridor, double density, LocalAvoidance avoidance, core::Random& random) {
  const auto people = static_cast<std::size_t>(std::max(1.0, std::round(density * corridor.length * corridor.width)));
  const double diameter = 2.0 * corridor.radius;
  const auto fitting_rows = static_cast<std::size_t>(std::max(1.0, std::floor(corridor.width / diameter)));
  const std::size_t rows = std::clamp<std::size_t>(static_cast<std::size_t>(std::round(corridor.width * std::sqrt(density))), 1, fitting_rows);
  const std::size_t columns = (people + rows - 1) / rows;
  const double dx = corridor.length / static_cast<double>(columns), dy = corridor.width / static_cast<double>(rows);
  const double jitter_x = std::max(0.0, (dx - diameter) / 2.0), jitter_y = std::max(0.0, (dy - diameter) / 2.0);
  std::vector<CrowdAgent> agents(people);
  for (std::size_t k = 0; k < people; ++k) {
    CrowdAgent& agent = agents[k];
    const double x = (static_cast<double>(k / rows) + 0.5) * dx, y = (static_cast<double>(k % rows) + 0.5) * dy;
    agent.position = {x + random.uniform(-jitter_x, jitter_x), y + random.uniform(-jitter_y, jitter_y)};
    const double spread = std::clamp(random.standard_normal(), -kSpeedSpreadLimit, kSpeedSpreadLimit);
    const double speed = corridor.speed_mean + corridor.speed_spread * spread;
    agent.preferred_velocity = {speed, 0.0};
    agent.max_speed = speed * kMaxSpeedFactor;
    agent.radius = corridor.radius;
    agent.avoidance = avoidance;
  }
  return agents;
}

}  // namespace

CorridorFigures walk_periodic_corridor(const PeriodicCorridor& corridor, double density, LocalAvoidance avoidance,
                                       const CrowdParams& params, std::uint64_t seed) {
  core::Random random = core::Random(seed).stream("periodic_corridor");
  std::vector<CrowdAgent> agents = lattice(corridor, density, avoidance, random);
  const std::size_t people = agents.size();
  Crowd crowd(params.orca, params.social_force, params.personal_space, params.headway);
  const double reach = ghost_reach(params, corridor);
  const ObstacleQuery walls = [&corridor](const Vec2& p, double range) -> std::optional<Vec2> {
    const bool lower = p.y() <= corridor.width - p.y();
    const Vec2 nearest(p.x(), lower ? 0.0 : corridor.width);
    if ((nearest - p).norm() > range) return std::nullopt;
    return nearest;
  };
  std::vector<CrowdAgent> with_ghosts;
  std::vector<Vec2> velocities;
  const auto settle_ticks = static_cast<std::int64_t>(std::llround(corridor.settle / corridor.dt));
  const auto measure_ticks = static_cast<std::int64_t>(std::llround(corridor.measure / corridor.dt));
  double speed_sum = 0.0;
  for (std::int64_t tick = 0; tick < settle_ticks + measure_ticks; ++tick) {
    with_ghosts.assign(agents.begin(), agents.end());
    for (const CrowdAgent& agent : agents) {
      if (agent.position.x() < reach) with_ghosts.push_back(agent), with_ghosts.back().position.x() += corridor.length;
      if (agent.position.x() > corridor.length - reach) with_ghosts.push_back(agent), with_ghosts.back().position.x() -= corridor.length;
    }
    crowd.compute_velocities(with_ghosts, walls, corridor.dt, velocities);
    for (std::size_t k = 0; k < people; ++k) {
      CrowdAgent& agent = agents[k];
      Vec2 to = agent.position + velocities[k] * corridor.dt;
      to.y() = std::clamp(to.y(), corridor.radius, corridor.width - corridor.radius);  // the walls' hard constraint
      agent.velocity = (to - agent.position) / corridor.dt;
      agent.position = {std::fmod(to.x() + corridor.length, corridor.length), to.y()};
      agent.personal_space = squeezed(agent.personal_space, agent.preferred_velocity.norm(), agent.velocity.norm(), corridor.dt);
      if (tick >= settle_ticks) speed_sum += agent.velocity.x();
    }
  }
  CorridorFigures figures;
  figures.density = static_cast<double>(people) / (corridor.length * corridor.width);
  figures.speed = speed_sum / static_cast<double>(people * static_cast<std::size_t>(measure_ticks));
  figures.specific_flow = figures.density * figures.speed;
  return figures;
}

PeriodicCorridor seyfried_single_file() {
  PeriodicCorridor ring;
  ring.length = kSeyfriedRingLength;
  ring.width = kSingleFileWidth;
  ring.speed_mean = kSeyfriedFreeSpeed;
  ring.speed_spread = kSeyfriedFreeSpeedSpread;
  return ring;
}

double seyfried_single_file_speed(double line_density) {
  return std::clamp((1.0 / line_density - kSeyfriedStandingSpace) / kSeyfriedTimeGap, 0.0, kSeyfriedFreeSpeed);
}

double weidmann_speed(double density) {
  if (density >= kWeidmannJamDensity) return 0.0;
  return kWeidmannFreeSpeed * (1.0 - std::exp(-kWeidmannGamma * (1.0 / density - 1.0 / kWeidmannJamDensity)));
}

}  // namespace hrisim::humans
