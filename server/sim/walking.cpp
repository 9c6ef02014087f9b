#include "sim/walking.hpp"

#include <algorithm>
#include <cmath>

#include "core/portable_math.hpp"
#include "sim/activities.hpp"
#include "sim/behaviours.hpp"
#include "sim/choreography.hpp"
#include "sim/doors_and_elevators.hpp"
#include "sim/events.hpp"
#include "sim/seats.hpp"

namespace hrisim::sim {
namespace {

using scenario::AgentKind;

/// `to`, kept inside the map's edge by `radius` (or, for `from` already nearer to it, by as much as
/// `from` is): outside, nothing can be planned.
Vec2 within_the_map(const world::OccupancyGrid& grid, const Vec2& from, const Vec2& to, double radius) {
  const Vec2 low = grid.origin(), high = low + Vec2(grid.width(), grid.height()) * grid.resolution();
  const auto inside = [&](double at, double lower, double upper, double was) {
    const double margin = std::min(radius, std::min(was - lower, upper - was));
    return std::clamp(at, lower + margin, std::max(lower + margin, upper - margin));
  };
  return {inside(to.x(), low.x(), high.x(), from.x()), inside(to.y(), low.y(), high.y(), from.y())};
}

/// How far `p` is from the nearest obstacle point within `range` (`range` when none is nearer).
double clearance_at(const scenario::Model& model, const State& state, const Vec2& p, double range) {
  const std::optional<Vec2> nearest = nearest_obstacle(model, state, p, range);
  return nearest ? (*nearest - p).norm() : range;
}

/// The disc a walker is to the crowd model and the walls: a person walking a path planned through a
/// passage only as wide as their body is that body (with their full disc, ORCA's obstacle line and the
/// hard constraint would hold them out of it) until they plan again; everyone else their radius.
double walking_radius(const scenario::AgentDef& def, const AgentState& self) {
  return self.navigation.fallback.body_clearance > 0.0 ? self.navigation.fallback.body_clearance : def.radius;
}

/// The group an agent belongs to now, -1 for none.
int group_of(const State& state, int agent) {
  for (std::size_t g = 0; g < state.groups.size(); ++g) {
    if (std::find(state.groups[g].begin(), state.groups[g].end(), agent) != state.groups[g].end()) return static_cast<int>(g);
  }
  return -1;
}

/// Whether an agent is done with its current waypoint (not the last): people within a step of it; a
/// robot's follower, which rounds corners itself, close to it or already past it along the next leg.
bool passed_waypoint(const scenario::AgentDef& def, const AgentState& self) {
  const Vec2& waypoint = self.navigation.path[self.navigation.path_index];
  if (!def.robot_model) return (waypoint - self.position).norm() < kWaypointReached;
  const Vec2& next = self.navigation.path[self.navigation.path_index + 1];
  return (waypoint - self.position).norm() < kRobotWaypointReached || (self.position - waypoint).dot(next - waypoint) > 0.0;
}

/// A human's gait, turn rate and motion primitive after it moved this tick and turned by `turned`.
void advance_body(const scenario::Model& model, const State& state, AgentState& self, double turned) {
  const double speed = self.velocity.norm();
  self.animation.turn_rate = turned / model.dt;
  const humans::MotionClip& walk = *humans::builtin_motion("walk");
  self.animation.gait_distance = std::fmod(self.animation.gait_distance + speed * model.dt + humans::kTurnStepRadius * std::abs(turned), walk.speed() * walk.duration());
  if (!self.animation.motion) return;
  // A primitive played for an action (a motion, a reach, sitting down or standing up) is not left for
  // a push.
  const bool playing = self.carrying.phase == ReachPhase::reaching || held_by_seat(self) ||
                       (!self.program.empty() && self.action_started && action_of(model, state, self.program.front()).kind == scenario::Action::Kind::play_motion);
  if (self.animation.motion_released_tick < 0 && !playing && speed > kMotionReleaseSpeed) self.animation.motion_released_tick = state.tick;
  if (self.animation.motion_released_tick >= 0 && static_cast<double>(state.tick - self.animation.motion_released_tick) * model.dt >= humans::kMotionBlendTime) {
    self.animation.motion = nullptr;
    self.animation.motion_released_tick = -1;
  }
}

/// How far the agent still has to walk: along its planned path, or straight to the goal without one.
double remaining_walk(const AgentState& self) {
  if (self.navigation.path_index >= self.navigation.path.size()) return (self.navigation.goal - self.position).norm();
  double length = (self.navigation.path[self.navigation.path_index] - self.position).norm();
  for (std::size_t k = self.navigation.path_index + 1; k < self.navigation.path.size(); ++k) length += (self.navigation.path[k] - self.navigation.path[k - 1]).norm();
  return length;
}

/// A person who has not come kStuckProgress closer to their goal (along their path: a detour round a
/// wall is progress) for kStuckTime is stuck (an event).
void note_progress(const scenario::Model& model, State& state, int agent) {
  AgentState& self = state.agents[agent];
  const double to_goal = remaining_walk(self);
  if (to_goal <= self.navigation.nearest_to_goal - kStuckProgress) {
    self.navigation.nearest_to_goal = to_goal;
    self.navigation.progress_tick = state.tick;
    self.navigation.stuck_reported = false;
  } else if (!self.navigation.stuck_reported && state.tick - self.navigation.progress_tick >= ticks(model, kStuckTime)) {
    self.navigation.stuck_reported = true;
    emit(model, state, model.agents[agent].id,
         events::Stuck{self.position.x(), self.position.y(), self.navigation.goal.x(), self.navigation.goal.y(), to_goal, static_cast<double>(state.tick - self.navigation.progress_tick) * model.dt});
  }
}

/// Where the agent wants to go this tick, before avoiding anyone; replans on the way when needed.
Vec2 preferred_velocity(const scenario::Model& model, State& state, std::size_t i, std::optional<double>& watching_heading) {
  AgentState& self = state.agents[i];
  Vec2 preferred = Vec2::Zero();
  if (self.navigation.under_way) {
    if (self.navigation.path.empty() && state.tick >= self.navigation.replan_at_tick) plan_path(model, state, static_cast<int>(i));
    if (!self.navigation.path.empty() && self.reaction.personal_space <= 0.0 && state.tick - self.navigation.planned_tick >= ticks(model, kStuckReplanInterval)) {
      // Held up for a whole squeeze time (humans::kSqueezeTime): the way round may be elsewhere, e.g. off a door
      // jamb that avoidance pressed the agent against.
      plan_path(model, state, static_cast<int>(i));
    } else if (!self.navigation.path.empty() && state.tick - self.navigation.planned_tick >= ticks(model, kReplanInterval)) {
      // Pushed too far off the leg by avoidance: rejoin the path from here without a search when a
      // straight way is free (local avoidance keeps the agent off the walls), else plan again.
      const Vec2& waypoint = self.navigation.path[self.navigation.path_index];
      const Vec2 nearest = core::closest_point_on_segment(self.position, self.navigation.leg_start, waypoint);
      const bool robot = model.agents[i].robot_model != nullptr;
      if ((nearest - self.position).norm() > (robot ? std::min(model.replan_distance, kRobotRejoinDistance) : model.replan_distance)) {
        // A robot's body would hit a wall its footprint grazes: it rejoins only with its whole radius free.
        const double clearance = (robot ? 1.0 : kRejoinClearance) * model.agents[i].radius;
        const world::Rejoin rejoin =
            model.planner.rejoin(self.position, self.navigation.leg_start, waypoint, clearance, blocked_door_cells(model, state, clearance));
        self.navigation.planned_tick = state.tick;
        // A robot's follower counts a corner it is beyond along the next leg as passed, so it would skip
        // the corner it should return to: it plans again instead, as a person far from the corner does.
        const bool corner_far = (self.navigation.leg_start - self.position).norm() > kCornerReturnReach;
        if (rejoin == world::Rejoin::replan || (rejoin == world::Rejoin::back_to_corner && (robot || corner_far))) {
          plan_path(model, state, static_cast<int>(i));
        } else {
          if (rejoin == world::Rejoin::back_to_corner) {
            self.navigation.path.insert(self.navigation.path.begin() + static_cast<std::ptrdiff_t>(self.navigation.path_index), self.navigation.leg_start);
          }
          self.navigation.leg_start = self.position;
        }
      }
    }
    while (self.navigation.path_index + 1 < self.navigation.path.size() && passed_waypoint(model.agents[i], self)) {
      self.navigation.leg_start = self.navigation.path[self.navigation.path_index];
      ++self.navigation.path_index;
    }
    const double to_goal = (self.navigation.goal - self.position).norm();
    if (to_goal <= self.navigation.goal_radius) {
      self.navigation.under_way = false;
      self.navigation.path.clear();
      self.navigation.hold = self.navigation.goal;
      if (self.navigation.goal_heading) self.attitude.target_heading = core::wrap_angle(*self.navigation.goal_heading);
    } else if (!self.navigation.path.empty()) {
      const Vec2 target = self.navigation.path[self.navigation.path_index];
      const bool last = self.navigation.path_index + 1 == self.navigation.path.size();
      const double speed = self.preferred_speed * (last ? std::clamp(to_goal / kArrivalSlowdown, 0.3, 1.0) : 1.0);
      preferred = (target - self.position).normalized() * speed;
    }
  }
  if (self.attitude.follow_leader.valid()) {
    const Vec2 to_spot = formation_target(state, static_cast<int>(i)) - self.position;
    const double speed = std::min(self.preferred_speed * humans::kMaxSpeedFactor, to_spot.norm() / kArrivalSlowdown * self.preferred_speed);
    preferred = to_spot.norm() > 1e-9 ? Vec2(to_spot.normalized() * speed) : Vec2::Zero();
  }
  if (self.attitude.harass_robot.valid()) {
    const AgentState& robot = state.agents[self.attitude.harass_robot.value];
    preferred = into_the_way(self, robot, self.attitude.harass_distance, self.preferred_speed);
    self.attitude.target_heading = core::direction_to(self.position, robot.position);
  }
  if (self.attitude.watched_robot.valid() && state.tick < self.attitude.watch_until_tick) {
    const Vec2 robot = state.agents[self.attitude.watched_robot.value].position;
    if ((robot - self.position).norm() <= self.attitude.watch_distance) {
      preferred = Vec2::Zero();
      watching_heading = core::direction_to(self.position, robot);
    }
  }
  if (!self.navigation.under_way && self.navigation.hold) {
    // Pushed aside while standing (making way in a queue): step back to the spot.
    const Vec2 back = *self.navigation.hold - self.position;
    if (back.norm() > kHoldTolerance) preferred = back.normalized() * std::min(kHoldSpeed, self.preferred_speed);
  }
  if (self.attitude.look_at_agent.valid()) self.attitude.target_heading = core::direction_to(self.position, state.agents[self.attitude.look_at_agent.value].position);
  if (model.agents[i].kind == AgentKind::human) preferred = react_to_robots(model, state, static_cast<int>(i), preferred, watching_heading);
  return preferred;
}

/// The clearances plan_path tries, in order (see walking.hpp).
std::vector<double> planning_clearances(const scenario::Model& model, const State& state, int agent) {
  const scenario::AgentDef& def = model.agents[agent];
  if (def.robot_model) return {def.radius + kRobotPathMargin, def.radius};
  const double body = std::min(body_clearance(model.grid), def.radius);
  if (body == def.radius) return {def.radius};
  // In a passage their disc does not fit, a plan with their radius would start outside it, maybe on the
  // side they came from.
  const AgentState& self = state.agents[agent];
  const bool in_narrow_passage = self.navigation.fallback.body_clearance > 0.0 && clearance_at(model, state, self.position, def.radius) < def.radius;
  if (in_narrow_passage) return {body, def.radius};
  return {def.radius, body};
}

/// After a path was planned with `clearance` (`smallest`: the least the agent ever plans with): an agent
/// standing where its body does not fit even at `smallest` (pushed or placed into a corner, a closed
/// door, an obstacle) had its plan started from the nearest free cell. It walks there first and says
/// so, once until a plan starts where it stands.
void recover_from_unplannable_spot(const scenario::Model& model, State& state, int agent, double clearance, double smallest,
                                   const std::vector<std::size_t>& blocked_cells) {
  AgentState& self = state.agents[agent];
  PlanningFallback& fallback = self.navigation.fallback;
  const std::size_t own = model.grid.index(model.grid.cell_of(self.position));  // a path was found: inside the map
  // A body that fits may still stand in a cell that does not (its centre nearer the wall): not unplannable.
  const auto unplannable = [&] {
    if (clearance_at(model, state, self.position, smallest) >= smallest) return false;
    std::vector<std::size_t> blocked = blocked_door_cells(model, state, smallest);
    std::sort(blocked.begin(), blocked.end());
    return !model.planner.traversable(own, smallest, blocked);
  };
  if (!unplannable()) {
    fallback.from_free_cell = false;
    return;
  }
  const std::optional<std::size_t> free = model.planner.nearest_traversable(own, clearance, blocked_cells);
  if (!free) return;  // not so: the planner started from it
  const Vec2 centre = model.grid.center_of(model.grid.cell_at(*free));
  self.navigation.path.insert(self.navigation.path.begin(), centre);
  if (fallback.from_free_cell) return;
  fallback.from_free_cell = true;
  emit(model, state, model.agents[agent].id, events::ReplannedFromFreeCell{self.position.x(), self.position.y(), centre.x(), centre.y()});
}

}  // namespace

double body_clearance(const world::OccupancyGrid& grid) { return std::max(kBodyHalfWidth - grid.resolution(), 0.0); }

Vec2 into_the_way(const AgentState& self, const AgentState& robot, double distance, double speed) {
  const Vec2 to_spot = robot.position + core::heading_vector(robot.heading) * distance - self.position;
  if (to_spot.norm() <= kInTheWayTolerance) return Vec2::Zero();
  return to_spot.normalized() * std::min(speed, to_spot.norm() / kArrivalSlowdown * speed);
}

std::optional<Vec2> nearest_obstacle(const scenario::Model& model, const State& state, const Vec2& p, double range) {
  std::optional<Vec2> nearest = model.field.nearest_obstacle(model.grid, p);
  for (std::size_t d = 0; d < model.doors.size(); ++d) {
    if (!door_blocks(state, static_cast<int>(d))) continue;
    const scenario::Door& door = model.doors[d];
    const Vec2 on_door = core::closest_point_on_segment(p, door.from, door.to);
    if (!nearest || (on_door - p).norm() < (*nearest - p).norm()) nearest = on_door;
  }
  if (!nearest || (*nearest - p).norm() > range) return std::nullopt;
  return nearest;
}

Vec2 clear_of_obstacles(const scenario::Model& model, const State& state, const Vec2& from, Vec2 to, double radius, double clearance) {
  // Most steps stay farther than `radius` from every obstacle: the clearance they set off with says so.
  if (clearance - (to - from).norm() < radius) {
    if (std::optional<Vec2> nearest = nearest_obstacle(model, state, to, radius)) {
      const double keep = clearance_at(model, state, from, radius);
      for (int pass = 0; pass < kClearancePasses && nearest; ++pass) {
        const Vec2 away = to - *nearest;
        const double distance = away.norm();
        if (distance >= keep) break;
        if (distance == 0.0) return from;
        to = *nearest + away * (keep / distance);
        nearest = nearest_obstacle(model, state, to, keep);
      }
      // A projection puts the centre at `keep` up to rounding: not a reason to stand still.
      if (nearest && (*nearest - to).norm() < keep - kClearanceRounding) return from;
    }
  }
  return within_the_map(model.grid, from, to, radius);
}

void walk(const scenario::Model& model, State& state, WalkingBuffers& buffers) {
  buffers.members.clear();
  for (std::size_t i = 0; i < state.agents.size(); ++i) {
    if (state.agents[i].active) buffers.members.push_back(i);
  }
  buffers.agents.resize(buffers.members.size());
  buffers.watching_headings.assign(state.agents.size(), std::nullopt);
  for (std::size_t k = 0; k < buffers.members.size(); ++k) {
    const std::size_t i = buffers.members[k];
    const Vec2 preferred = preferred_velocity(model, state, i, buffers.watching_headings[i]);
    const AgentState& self = state.agents[i];
    const scenario::AgentDef& def = model.agents[i];
    humans::CrowdAgent& crowd = buffers.agents[k];
    crowd.position = self.position;
    crowd.radius = walking_radius(def, self);
    crowd.avoidance = def.avoidance;
    // A controlled agent keeps its velocity: robots, people held in place (rooted, on a seat, or
    // seated or lying where they are going nowhere: others walk round them), and people stepping onto
    // or off a seat's spot, where the furniture is too close for avoidance.
    const bool held = self.rooted || held_by_seat(self) || (!self.navigation.under_way && self.animation.motion && posture_of(self) != scenario::Posture::standing);
    const std::optional<Vec2> stepping = seat_step_velocity(model, state, static_cast<int>(i));
    if (stepping) buffers.watching_headings[i] = model.seats[self.seating.seat.value].pose.theta;  // backing onto the seat, facing its way
    crowd.controlled = def.kind == AgentKind::robot || held || stepping;
    crowd.preferred_velocity = preferred;
    crowd.personal_space = self.reaction.personal_space;
    crowd.robots_as_obstacles = self.reaction.behaviour.type == humans::BehaviourType::impassive;
    // Members of one group, and people sharing a place (a cabin, a social space's or a waiting line's
    // places), stand as close as it has them.
    crowd.group = group_of(state, static_cast<int>(i));
    crowd.place = self.queueing.queue.valid() && self.queueing.place >= 0 ? static_cast<int>(model.social_spaces.size()) + self.queueing.queue.value : self.reservation.space.value;
    crowd.max_speed = std::max(self.preferred_speed * humans::kMaxSpeedFactor, 1e-3);
    crowd.velocity = !crowd.controlled ? self.velocity
                     : stepping        ? *stepping
                     : held            ? Vec2::Zero()
                     : def.robot_model ? self.velocity  // where its base is taking it
                     : self.navigation.under_way ? preferred
                                       : self.commanded_velocity;
  }
  const humans::ObstacleQuery obstacles = [&model, &state](const Vec2& p, double range) { return nearest_obstacle(model, state, p, range); };
  buffers.crowd.compute_velocities(buffers.agents, obstacles, model.dt, buffers.velocities);

  const double max_turn = kTurnRate * model.dt;
  for (std::size_t k = 0; k < buffers.members.size(); ++k) {
    const std::size_t i = buffers.members[k];
    if (model.agents[i].robot_model) continue;  // a robot with a model moves by its own base
    AgentState& self = state.agents[i];
    const std::optional<double>& watching = buffers.watching_headings[i];
    const Vec2 to = self.position + buffers.velocities[k] * model.dt;
    // Walkers the crowd model moved stay out of walls; others (stepping onto a seat, held) are placed.
    const Vec2 clear = buffers.agents[k].controlled ? to
                                                    : clear_of_obstacles(model, state, self.position, to, buffers.agents[k].radius,
                                                                         buffers.crowd.obstacle_distances()[k]);
    self.velocity = clear == to ? buffers.velocities[k] : (clear - self.position) / model.dt;
    self.position = clear;
    self.reaction.personal_space =
        humans::squeezed(self.reaction.personal_space, buffers.agents[k].preferred_velocity.norm(), self.velocity.norm(), model.dt);
    const double heading_before = self.heading;
    // A seated body faces the seat's way: a look or a turn asked of a seated person is over at once.
    const bool seated = held_by_seat(self);
    if (seated) self.attitude.target_heading.reset();
    std::optional<double> desired = seated ? std::nullopt : watching ? watching : self.attitude.target_heading;
    // Walking direction, for every walker every tick: the polynomial (1e-5 rad) spares a libm call.
    if (!desired && !seated && self.velocity.norm() > 0.05) desired = core::polynomial_atan2(self.velocity.y(), self.velocity.x());
    if (desired) {
      const double difference = core::wrap_angle(*desired - self.heading);
      if (std::abs(difference) <= max_turn) {
        self.heading = core::wrap_angle(*desired);
        if (!watching && self.attitude.target_heading && std::abs(difference) <= kHeadingTolerance) self.attitude.target_heading.reset();
      } else {
        self.heading = core::wrap_angle(self.heading + std::copysign(max_turn, difference));
      }
    }
    if (model.agents[i].kind == AgentKind::human) {
      advance_body(model, state, self, core::wrap_angle(self.heading - heading_before));
      if (self.navigation.under_way) note_progress(model, state, static_cast<int>(i));
    }
  }
}

void go_to(const scenario::Model& model, State& state, int agent, const Pose2& goal, double radius, bool with_heading) {
  AgentState& self = state.agents[agent];
  self.navigation.under_way = true;
  self.navigation.hold.reset();
  self.navigation.goal = goal.position();
  self.navigation.goal_radius = radius;
  self.navigation.goal_heading = with_heading ? std::optional<double>(goal.theta) : std::nullopt;
  self.attitude.target_heading.reset();
  self.navigation.replan_at_tick = -1;
  self.navigation.progress_tick = state.tick;
  self.navigation.stuck_reported = false;
  plan_path(model, state, agent);
  self.navigation.nearest_to_goal = remaining_walk(self);
}

bool plan_path(const scenario::Model& model, State& state, int agent) {
  AgentState& self = state.agents[agent];
  const scenario::AgentDef& def = model.agents[agent];
  const std::vector<double> clearances = planning_clearances(model, state, agent);
  std::optional<std::vector<Vec2>> path;
  double clearance = 0.0;
  std::vector<std::size_t> blocked;
  for (std::size_t k = 0; k < clearances.size() && !path; ++k) {
    clearance = clearances[k];
    blocked = blocked_door_cells(model, state, clearance);
    path = model.planner.plan(self.position, self.navigation.goal, clearance, blocked, state.planning_history);
  }
  self.navigation.path_index = 0;
  self.navigation.leg_start = self.position;
  self.navigation.planned_tick = state.tick;
  if (path) {
    self.navigation.path = std::move(*path);
    self.navigation.replan_at_tick = -1;
    self.navigation.fallback.body_clearance = clearance < def.radius && !def.robot_model ? clearance : 0.0;
    recover_from_unplannable_spot(model, state, agent, clearance, std::min(clearances.front(), clearances.back()), blocked);
    return true;
  }
  self.navigation.path.clear();
  if (self.navigation.replan_at_tick < 0) emit(model, state, def.id, events::GoalUnreachable{self.navigation.goal.x(), self.navigation.goal.y()});
  self.navigation.replan_at_tick = state.tick + ticks(model, kReplanRetry);
  return false;
}

Vec2 formation_target(const State& state, int agent) {
  const AgentState& self = state.agents[agent];
  const AgentState& leader = state.agents[self.attitude.follow_leader.value];
  const double heading = leader.velocity.norm() > 0.05 ? std::atan2(leader.velocity.y(), leader.velocity.x()) : leader.heading;
  const Pose2 spot = core::compose({leader.position.x(), leader.position.y(), heading}, {self.attitude.formation_offset.x(), self.attitude.formation_offset.y(), 0.0});
  return spot.position();
}

}  // namespace hrisim::sim
