#include "humans/locomotion.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/portable_math.hpp"

namespace hrisim::humans {
namespace {

using core::cross;

constexpr double kEpsilon = 1e-5;  // RVO_EPSILON


bool linear_program1(const std::vector<OrcaLine>& lines, std::size_t line_no, double radius, const Vec2& optimum,
                     bool direction_optimisation, Vec2& result) {
  const OrcaLine& line = lines[line_no];
  const double dot = line.point.dot(line.direction);
  const double discriminant = dot * dot + radius * radius - line.point.squaredNorm();
  if (discriminant < 0.0) return false;  // the max-speed circle misses the line entirely
  const double root = std::sqrt(discriminant);
  double t_left = -dot - root, t_right = -dot + root;
  for (std::size_t i = 0; i < line_no; ++i) {
    const double denominator = cross(line.direction, lines[i].direction);
    const double numerator = cross(lines[i].direction, line.point - lines[i].point);
    if (std::abs(denominator) <= kEpsilon) {
      if (numerator < 0.0) return false;  // parallel and on the wrong side
      continue;
    }
    const double t = numerator / denominator;
    if (denominator >= 0.0) {
      t_right = std::min(t_right, t);
    } else {
      t_left = std::max(t_left, t);
    }
    if (t_left > t_right) return false;
  }
  if (direction_optimisation) {
    result = line.point + (optimum.dot(line.direction) > 0.0 ? t_right : t_left) * line.direction;
  } else {
    const double t = std::clamp(line.direction.dot(optimum - line.point), t_left, t_right);
    result = line.point + t * line.direction;
  }
  return true;
}

std::size_t linear_program2(const std::vector<OrcaLine>& lines, double radius, const Vec2& optimum,
                            bool direction_optimisation, Vec2& result) {
  if (direction_optimisation) {
    result = optimum * radius;
  } else if (optimum.squaredNorm() > radius * radius) {
    result = optimum.normalized() * radius;
  } else {
    result = optimum;
  }
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (cross(lines[i].direction, lines[i].point - result) > 0.0) {
      const Vec2 previous = result;
      if (!linear_program1(lines, i, radius, optimum, direction_optimisation, result)) {
        result = previous;
        return i;
      }
    }
  }
  return lines.size();
}

void linear_program3(const std::vector<OrcaLine>& lines, std::size_t obstacle_lines, std::size_t begin_line,
                     double radius, Vec2& result) {
  double distance = 0.0;
  for (std::size_t i = begin_line; i < lines.size(); ++i) {
    if (cross(lines[i].direction, lines[i].point - result) <= distance) continue;
    std::vector<OrcaLine> projected(lines.begin(), lines.begin() + static_cast<std::ptrdiff_t>(obstacle_lines));
    for (std::size_t j = obstacle_lines; j < i; ++j) {
      OrcaLine line;
      const double determinant = cross(lines[i].direction, lines[j].direction);
      if (std::abs(determinant) <= kEpsilon) {
        if (lines[i].direction.dot(lines[j].direction) > 0.0) continue;  // same direction
        line.point = 0.5 * (lines[i].point + lines[j].point);
      } else {
        line.point = lines[i].point +
                     (cross(lines[j].direction, lines[i].point - lines[j].point) / determinant) * lines[i].direction;
      }
      line.direction = (lines[j].direction - lines[i].direction).normalized();
      projected.push_back(line);
    }
    const Vec2 previous = result;
    if (linear_program2(projected, radius, core::left_normal(lines[i].direction), true, result) < projected.size()) {
      result = previous;  // should not happen in principle: keep the last feasible answer
    }
    distance = cross(lines[i].direction, lines[i].point - result);
  }
}

}  // namespace

OrcaLine orca_line(const Vec2& position, const Vec2& velocity, double radius, const Vec2& other_position,
                   const Vec2& other_velocity, double other_radius, double time_horizon, double dt,
                   double responsibility) {
  const Vec2 relative_position = other_position - position;
  const Vec2 relative_velocity = velocity - other_velocity;
  const double distance_squared = relative_position.squaredNorm();
  const double combined_radius = radius + other_radius;
  const double combined_radius_squared = combined_radius * combined_radius;
  OrcaLine line;
  Vec2 u;
  if (distance_squared > combined_radius_squared) {
    const double inverse_horizon = 1.0 / time_horizon;
    const Vec2 w = relative_velocity - inverse_horizon * relative_position;  // from cut-off centre to velocity
    const double w_length_squared = w.squaredNorm();
    const double dot1 = w.dot(relative_position);
    if (dot1 < 0.0 && dot1 * dot1 > combined_radius_squared * w_length_squared) {
      const double w_length = std::sqrt(w_length_squared);  // project on the cut-off circle
      const Vec2 unit_w = w / w_length;
      line.direction = Vec2(unit_w.y(), -unit_w.x());
      u = (combined_radius * inverse_horizon - w_length) * unit_w;
    } else {
      const double leg = std::sqrt(distance_squared - combined_radius_squared);  // project on a leg
      if (cross(relative_position, w) > 0.0) {
        line.direction = Vec2(relative_position.x() * leg - relative_position.y() * combined_radius,
                              relative_position.x() * combined_radius + relative_position.y() * leg) /
                         distance_squared;
      } else {
        line.direction = -Vec2(relative_position.x() * leg + relative_position.y() * combined_radius,
                               -relative_position.x() * combined_radius + relative_position.y() * leg) /
                         distance_squared;
      }
      u = relative_velocity.dot(line.direction) * line.direction - relative_velocity;
    }
  } else {
    // Already overlapping: resolve within one time step.
    const double inverse_step = 1.0 / dt;
    const Vec2 w = relative_velocity - inverse_step * relative_position;
    const double w_length = w.norm();
    const Vec2 unit_w = w_length > 0.0 ? Vec2(w / w_length) : Vec2(-relative_position.normalized());
    line.direction = Vec2(unit_w.y(), -unit_w.x());
    u = (combined_radius * inverse_step - w_length) * unit_w;
  }
  line.point = velocity + responsibility * u;
  return line;
}

namespace {

/// The social force model's interaction force on a from b (Moussaïd et al. 2009 as pedsim computes
/// it) for each pair given as columns; zero for agents at the same spot. Cloned for wider vector
/// units: each lane does the same IEEE operations in the same order, so every clone gives the same bits.
/// (GCC 12 vectorises this loop only while the columns are read by index, not into locals first.)
#if defined(__clang__)  // clang (the fuzz preset) refuses clones that are noinline; one version serves there
#define HRISIM_VECTOR_CLONES
#else
#define HRISIM_VECTOR_CLONES [[gnu::target_clones("avx512f", "avx2", "default"), gnu::noinline]]
#endif
HRISIM_VECTOR_CLONES
void interaction_forces(const SocialForceParams& p, std::size_t count, const float* dx, const float* dy,
                        const float* dvx, const float* dvy, float* fx, float* fy) {
  const auto lambda = static_cast<float>(p.lambda), gamma = static_cast<float>(p.gamma);  // not aliased by fx, fy
  const auto n = static_cast<float>(p.n), n_prime = static_cast<float>(p.n_prime);
  for (std::size_t k = 0; k < count; ++k) {
    const float distance = std::sqrt(dx[k] * dx[k] + dy[k] * dy[k]);
    const bool apart = distance > 0.0f;
    const float safe_distance = apart ? distance : 1.0f;
    const float ex = dx[k] / safe_distance, ey = dy[k] / safe_distance;
    const float ix = lambda * dvx[k] + ex, iy = lambda * dvy[k] + ey;
    const float length = std::sqrt(ix * ix + iy * iy);
    const bool valid = apart && length > 0.0f;
    const float safe_length = valid ? length : 1.0f;
    const float tx = ix / safe_length, ty = iy / safe_length;
    const float range = gamma * safe_length;  // pedsim's B
    const float distance_term = distance / range;
    const float theta = core::polynomial_atan2(tx * ey - ty * ex, tx * ex + ty * ey);
    const float velocity_term = n_prime * range * theta, angle_term = n * range * theta;
    const float velocity_amount = -core::exp_nonpositive(-distance_term - velocity_term * velocity_term);
    const float angle_amount =
        (theta >= 0.0f ? -1.0f : 1.0f) * core::exp_nonpositive(-distance_term - angle_term * angle_term);
    // velocity_amount along the interaction direction, angle_amount along its left normal (-ty, tx)
    fx[k] = valid ? velocity_amount * tx - angle_amount * ty : 0.0f;
    fy[k] = valid ? velocity_amount * ty + angle_amount * tx : 0.0f;
  }
}

}  // namespace

Vec2 interaction_force(const SocialForceParams& params, const Vec2& offset, const Vec2& velocity_difference) {
  const auto dx = static_cast<float>(offset.x()), dy = static_cast<float>(offset.y());
  const auto dvx = static_cast<float>(velocity_difference.x()), dvy = static_cast<float>(velocity_difference.y());
  float fx = 0.0f, fy = 0.0f;
  interaction_forces(params, 1, &dx, &dy, &dvx, &dvy, &fx, &fy);
  return {static_cast<double>(fx), static_cast<double>(fy)};
}

Vec2 obstacle_force(const SocialForceParams& params, const Vec2& position, double radius, const Vec2& obstacle) {
  const Vec2 away = position - obstacle;
  const double length = away.norm();
  if (length <= 0.0) return Vec2::Zero();
  return std::exp(-(length - radius) / params.obstacle_sigma) * away / length;
}

Vec2 solve_orca(const std::vector<OrcaLine>& lines, std::size_t obstacle_lines, double max_speed,
                const Vec2& preferred) {
  Vec2 result;
  const std::size_t failed = linear_program2(lines, max_speed, preferred, false, result);
  if (failed < lines.size()) linear_program3(lines, obstacle_lines, failed, max_speed, result);
  return result;
}

CrowdParams crowd_preset(CrowdPreset preset) {
  CrowdParams params;
  if (preset == CrowdPreset::calibrated) {
    params.headway.time_gap = kCalibratedTimeGap;
    params.personal_space.from_people = 0.0;
    params.social_force.obstacle_sigma = kCalibratedObstacleSigma;
    params.social_force.obstacle_factor = kCalibratedObstacleFactor;
  }
  if (preset == CrowdPreset::crowdnav) {
    params.orca = {.neighbour_distance = 10.0, .max_neighbours = 10, .time_horizon = 5.0, .obstacle_horizon = 5.0};
    params.personal_space = {.from_robots = 0.0, .from_people = 0.0};
  }
  return params;
}

std::optional<CrowdPreset> crowd_preset_named(std::string_view name) {
  if (name == "hrisim") return CrowdPreset::hrisim;
  if (name == "calibrated") return CrowdPreset::calibrated;
  if (name == "crowdnav") return CrowdPreset::crowdnav;
  return std::nullopt;
}

Crowd::Crowd(OrcaParams orca, SocialForceParams social_force, PersonalSpace personal_space, Headway headway)
    : orca_(orca), social_force_(social_force), personal_space_(personal_space), headway_(headway), grid_(std::max(orca.neighbour_distance, 1.0)), social_pairs_(1), scratch_(1) {}

/// No agent's body is wider than this round its centre, m (bounds the search for neighbours).
constexpr double kLargestBodyRadius = 1.0;

double Crowd::margin(const CrowdAgent& agent, const CrowdAgent& other) const {
  // Limbs reach beyond the disc whatever margin is asked for: without it, a swinging foot would touch.
  const double limbs = kLimbClearance;
  double wanted = 0.0;
  if (other.controlled) {
    // A robot sharing the place (riding the cabin too) is as close as the place has it.
    const bool shared = agent.place >= 0 && agent.place == other.place;
    wanted = shared || agent.robots_as_obstacles ? limbs : std::max(agent.personal_space * personal_space_.from_robots, limbs);
  } else if (!(agent.group >= 0 && agent.group == other.group) && !(agent.place >= 0 && agent.place == other.place)) {
    wanted = agent.personal_space * personal_space_.from_people;
  }
  const double gap = (other.position - agent.position).norm() - agent.radius - other.radius;
  return std::clamp(gap, 0.0, wanted);
}

Vec2 Crowd::keep_personal_space(std::size_t i, std::span<const CrowdAgent> agents, Vec2 velocity, double dt, Scratch& scratch) const {
  const CrowdAgent& agent = agents[i];
  std::vector<std::pair<double, std::uint32_t>>& neighbours = scratch.neighbours;
  const double reach = agent.radius + personal_space_.from_robots + agent.max_speed * dt + kLargestBodyRadius;
  grid_.nearest_within(agent.position, reach, agents.size(), static_cast<std::uint32_t>(i), neighbours);
  for (const auto& [squared_distance, j] : neighbours) {
    const CrowdAgent& other = agents[j];
    const double keep = margin(agent, other);
    const double distance = std::sqrt(squared_distance);
    if (keep <= 0.0 || distance <= 0.0) continue;  // the social force alone, as pedsim has it
    const Vec2 offset = other.position - agent.position;
    const Vec2 towards = offset / distance;
    // No nearer than the margin after this tick: the closing speed is capped by the room left.
    const double room = distance - agent.radius - other.radius - keep;
    const double closing = (velocity - other.velocity).dot(towards), allowed = std::max(room, 0.0) / dt;
    if (closing > allowed) velocity -= (closing - allowed) * towards;
  }
  return velocity;
}

void Crowd::compute_velocities(std::span<const CrowdAgent> agents, const ObstacleQuery& obstacles, double dt,
                               std::vector<Vec2>& velocities) {
  positions_.resize(agents.size());
  for (std::size_t i = 0; i < agents.size(); ++i) positions_[i] = agents[i].position;
  grid_.rebuild(positions_);
  velocities.resize(agents.size());
  obstacle_distances_.assign(agents.size(), 0.0);
  add_social_forces(agents);
  const auto part = [&](unsigned k, std::size_t begin, std::size_t end) {
    Scratch& scratch = scratch_[k];
    for (std::size_t i = begin; i < end; ++i) {
      const CrowdAgent& agent = agents[i];
      if (agent.controlled || agent.replayed) {
        velocities[i] = agent.velocity;
        continue;
      }
      const Vec2 preferred = headway_.time_gap > 0.0 ? within_headway(i, agents, obstacles, scratch) : agent.preferred_velocity;
      if (agent.avoidance == LocalAvoidance::orca) {
        velocities[i] = orca_velocity(i, agents, preferred, obstacles, dt, scratch, obstacle_distances_[i]);
      } else {
        velocities[i] = social_force_velocity(i, agents, preferred, obstacles, dt, scratch, obstacle_distances_[i]);
      }
    }
  };
  if (team_ && agents.size() >= kCrowdToShare) {
    team_->run(agents.size(), part);
  } else {
    part(0, 0, agents.size());
  }
}

void Crowd::set_threads(unsigned threads) {
  team_ = threads > 1 ? std::make_unique<core::ThreadTeam>(threads) : nullptr;
  scratch_.resize(std::max(threads, 1u));
  social_pairs_.resize(std::max(threads, 1u));
}

Vec2 Crowd::within_headway(std::size_t i, std::span<const CrowdAgent> agents, const ObstacleQuery& obstacles, Scratch& scratch) const {
  const CrowdAgent& agent = agents[i];
  const double speed = agent.preferred_velocity.norm();
  if (speed <= 0.0) return agent.preferred_velocity;
  const double horizon = headway_.horizon;
  std::vector<std::pair<double, std::uint32_t>>& neighbours = scratch.neighbours;
  grid_.nearest_within(agent.position, horizon + agent.radius + kLargestBodyRadius, agents.size(), static_cast<std::uint32_t>(i), neighbours);
  const std::optional<Vec2> obstacle = obstacles(agent.position, horizon + agent.radius);
  // The nearest obstacle stands for a wall through it, square to the way to it.
  const Vec2 wall_normal = obstacle ? Vec2((agent.position - *obstacle).normalized()) : Vec2::Zero();
  const double wall_room = obstacle ? (agent.position - *obstacle).norm() - agent.radius : 0.0;
  // A way may run into a wall other than the nearest (across a narrow corridor): the obstacle nearest
  // the middle of the walk that sets the speed, the way's first time gap at full speed, stands for a
  // wall through it too. Its disc holds every obstacle the body would meet on that walk.
  const double walk = std::min(horizon, speed * headway_.time_gap);
  const auto wall_on_the_way = [&](const Vec2& way) {
    const Vec2 middle = agent.position + way * (walk / 2.0);
    const std::optional<Vec2> met = obstacles(middle, walk / 2.0 + agent.radius);
    if (!met) return horizon;
    if (*met == middle) return std::max(walk / 2.0 - agent.radius, 0.0);  // the way's middle is in the wall
    Vec2 normal = (middle - *met).normalized();
    if ((agent.position - *met).dot(normal) < 0.0) normal = -normal;  // the middle is past the wall
    const double towards = -way.dot(normal);
    return towards > 0.0 ? std::max((agent.position - *met).dot(normal) - agent.radius, 0.0) / towards : horizon;
  };
  // How far the agent walks along `way` before its body touches someone's where they are now (as the
  // collision-free speed model measures spacing), or a wall: Moussaïd et al.'s f(α), capped at the
  // horizon. It both ranks the ways and sets the speed.
  const auto gap_ahead = [&](const Vec2& way) {
    double gap = wall_on_the_way(way);
    for (const auto& [squared_distance, j] : neighbours) {
      const Vec2 offset = agents[j].position - agent.position;
      const double ahead = offset.dot(way), aside = std::abs(cross(way, offset)), touching = agent.radius + agents[j].radius;
      if (ahead <= 0.0 || aside >= touching) continue;  // behind, or not in the agent's lane
      gap = std::min(gap, std::max(ahead - std::sqrt(touching * touching - aside * aside), 0.0));
    }
    const double towards_wall = -way.dot(wall_normal);
    if (towards_wall > 0.0) gap = std::min(gap, std::max(wall_room, 0.0) / towards_wall);
    return gap;
  };
  const double wanted = std::atan2(agent.preferred_velocity.y(), agent.preferred_velocity.x());
  Vec2 best_way = agent.preferred_velocity / speed;
  double best_gap = gap_ahead(best_way);
  // Moussaïd et al.'s d(α)²: how far from the destination (at the horizon, the way wanted) walking
  // f(α) along α leaves the agent; ties keep the way nearer the one wanted.
  double best_miss = horizon * horizon + best_gap * best_gap - 2.0 * horizon * best_gap;
  for (int k = 1; k <= kHeadwayWaysEachSide; ++k) {
    const double turn = headway_.field_of_view * k / kHeadwayWaysEachSide;
    for (const double side : {1.0, -1.0}) {
      const Vec2 way = core::heading_vector(wanted + side * turn);
      const double gap = gap_ahead(way);
      const double miss = horizon * horizon + gap * gap - 2.0 * horizon * gap * std::cos(turn);
      if (miss < best_miss) best_way = way, best_gap = gap, best_miss = miss;
    }
  }
  return best_way * std::min(speed, best_gap / headway_.time_gap);
}

Vec2 Crowd::orca_velocity(std::size_t i, std::span<const CrowdAgent> agents, const Vec2& preferred, const ObstacleQuery& obstacles,
                          double dt, Scratch& scratch, double& obstacle_distance) const {
  const CrowdAgent& agent = agents[i];
  std::vector<OrcaLine>& lines = scratch.lines;
  lines.clear();
  std::size_t obstacle_lines = 0;
  const double obstacle_range = agent.max_speed * orca_.obstacle_horizon + agent.radius;
  const auto obstacle = obstacles(agent.position, obstacle_range);
  obstacle_distance = obstacle ? (*obstacle - agent.position).norm() : obstacle_range;
  if (obstacle) {
    lines.push_back(orca_line(agent.position, agent.velocity, agent.radius, *obstacle, Vec2::Zero(), 0.0,
                              orca_.obstacle_horizon, dt, 1.0));
    obstacle_lines = 1;
  }
  // The closest neighbours, ties broken by index so the choice is deterministic.
  std::vector<std::pair<double, std::uint32_t>>& neighbours = scratch.neighbours;
  grid_.nearest_within(agent.position, orca_.neighbour_distance, static_cast<std::size_t>(orca_.max_neighbours),
                       static_cast<std::uint32_t>(i), neighbours);
  for (const auto& [squared_distance, j] : neighbours) {
    const CrowdAgent& other = agents[j];
    lines.push_back(orca_line(agent.position, agent.velocity, agent.radius, other.position, other.velocity,
                              other.radius + margin(agent, other), orca_.time_horizon, dt, other.controlled || other.replayed ? 1.0 : 0.5));
  }
  return solve_orca(lines, obstacle_lines, agent.max_speed, preferred);
}

void Crowd::add_social_forces(std::span<const CrowdAgent> agents) {
  social_.assign(agents.size(), Vec2::Zero());
  const auto feels = [](const CrowdAgent& agent) {
    return agent.avoidance == LocalAvoidance::social_force && !agent.controlled;
  };
  if (std::none_of(agents.begin(), agents.end(), feels)) return;  // no one to move
  // Positions and velocities in the grid's slot order, so the pair search reads contiguous memory.
  // Each candidate's differences are written without a branch and kept (the count advances) when it is
  // within range; then all forces are computed in one loop (it vectorises) and summed in scan order.
  // Each pair's force is computed once and the force on b is exactly the opposite: swapping the agents
  // negates every input.
  const auto items = grid_.items();
  const std::size_t count = items.size();
  slot_velocities_.resize(count);
  for (std::size_t k = 0; k < count; ++k) slot_velocities_[k] = agents[items[k]].velocity;
  const auto positions = grid_.sorted_positions();
  const double range_squared = social_force_.neighbour_distance * social_force_.neighbour_distance;
  // Each thread gathers the pairs of its slots and computes their forces; the sums are then made on
  // this thread, part after part, in the order a single scan gives.
  const auto gather = [&](unsigned part, std::size_t first, std::size_t last) {
    SocialPairs& pairs = social_pairs_[part];
    std::size_t kept = 0;
    grid_.for_each_candidate_run(
        social_force_.neighbour_distance,
        [&](std::uint32_t a, std::uint32_t begin, std::uint32_t end) {
          if (pairs.a.size() < kept + (end - begin)) pairs.resize(2 * (kept + (end - begin)));
          for (std::uint32_t b = begin; b < end; ++b) {
            const Vec2 difference = positions[b] - positions[a];
            const Vec2 velocity_difference = slot_velocities_[a] - slot_velocities_[b];
            pairs.a[kept] = a;
            pairs.b[kept] = b;
            pairs.dx[kept] = static_cast<float>(difference.x());
            pairs.dy[kept] = static_cast<float>(difference.y());
            pairs.dvx[kept] = static_cast<float>(velocity_difference.x());
            pairs.dvy[kept] = static_cast<float>(velocity_difference.y());
            kept += difference.squaredNorm() <= range_squared ? 1 : 0;
          }
        },
        static_cast<std::uint32_t>(first), static_cast<std::uint32_t>(last));
    interaction_forces(social_force_, kept, pairs.dx.data(), pairs.dy.data(), pairs.dvx.data(), pairs.dvy.data(), pairs.fx.data(),
                       pairs.fy.data());
    pairs.kept = kept;
  };
  const bool shared = team_ && count >= kCrowdToShare;
  if (shared) {
    team_->run(count, gather);
  } else {
    gather(0, 0, count);
  }
  slot_social_.assign(count, Vec2::Zero());
  // Only this tick's parts: a crowd that has shrunk below kCrowdToShare leaves older ones behind.
  for (std::size_t part = 0; part < (shared ? social_pairs_.size() : 1); ++part) {
    const SocialPairs& pairs = social_pairs_[part];
    for (std::size_t k = 0; k < pairs.kept; ++k) {
      const Vec2 force(static_cast<double>(pairs.fx[k]), static_cast<double>(pairs.fy[k]));
      slot_social_[pairs.a[k]] += force;
      slot_social_[pairs.b[k]] -= force;
    }
  }
  for (std::size_t k = 0; k < count; ++k) {
    if (feels(agents[items[k]])) social_[items[k]] = slot_social_[k];
  }
}

void SocialPairs::resize(std::size_t size) {
  for (auto* column : {&dx, &dy, &dvx, &dvy, &fx, &fy}) column->resize(size);
  a.resize(size);
  b.resize(size);
}

Vec2 Crowd::social_force_velocity(std::size_t i, std::span<const CrowdAgent> agents, const Vec2& preferred,
                                  const ObstacleQuery& obstacles, double dt, Scratch& scratch, double& obstacle_distance) const {
  const CrowdAgent& agent = agents[i];
  const SocialForceParams& p = social_force_;
  const Vec2 desired = (preferred - agent.velocity) / p.relaxation_time;
  const Vec2& social = social_[i];

  const auto obstacle = obstacles(agent.position, p.neighbour_distance);
  obstacle_distance = obstacle ? (*obstacle - agent.position).norm() : p.neighbour_distance;
  const Vec2 obstacle_force = obstacle ? humans::obstacle_force(p, agent.position, agent.radius, *obstacle) : Vec2::Zero();

  const Vec2 acceleration = p.desired_factor * desired + p.social_factor * social + p.obstacle_factor * obstacle_force;
  Vec2 velocity = agent.velocity + acceleration * dt;
  if (velocity.norm() > agent.max_speed) velocity = velocity.normalized() * agent.max_speed;
  return keep_personal_space(i, agents, velocity, dt, scratch);
}

}  // namespace hrisim::humans
