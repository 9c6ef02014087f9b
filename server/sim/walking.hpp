#pragma once
// Walking: each agent's preferred velocity (its path, its place in a formation, a robot it stands in
// the way of or watches, the spot it holds), replanning when avoidance pushed it off its path, then
// the crowd model (ORCA or social force) gives every new velocity, and people move and turn.
#include <optional>
#include <vector>

#include "humans/locomotion.hpp"
#include "scenario/model.hpp"
#include "sim/state.hpp"

namespace hrisim::sim {

/// Turning speed of humans, rad/s.
inline constexpr double kTurnRate = 3.0;
/// A turn or look-at is complete within this angle, rad.
inline constexpr double kHeadingTolerance = 0.05;
/// Humans slow down over this distance before their goal, m.
inline constexpr double kArrivalSlowdown = 0.5;
/// A waypoint (other than the last) counts as passed within this distance, m.
inline constexpr double kWaypointReached = 0.3;
/// A robot's path follower turns a corner itself: its waypoint counts as passed within this distance,
/// or once the robot is past it along the next leg, m.
inline constexpr double kRobotWaypointReached = 0.1;
/// Robots plan their paths this far off walls and furniture beyond their radius, where the way is wide
/// enough, m: a path follower cuts corners, and walls stop a robot's body.
inline constexpr double kRobotPathMargin = 0.1;
/// Half the breadth of an adult's body at the shoulders, m: the clearance a person plans with through
/// a passage their disc (their radius, which leaves room for swinging limbs) does not fit, and keeps
/// from walls while walking such a path. Adults' bideltoid shoulder breadth runs from about 0.40 m
/// (5th percentile, women) to about 0.51 m (95th percentile, men) in DIN 33402-2 and ISO 7250 surveys;
/// a 0.5 m passage lets nearly everyone through, turning the shoulders a little at most.
inline constexpr double kBodyHalfWidth = 0.25;
/// The clearance a person plans and walks with through such a passage on `grid`: kBodyHalfWidth less a
/// cell, as a wall's blocked cells reach up to a cell into the floor (the planner leaves a door D wide
/// about D / 2 less a cell each side of its middle); never below 0.
double body_clearance(const world::OccupancyGrid& grid);
/// A standing agent pushed further than this from where it arrived steps back, m...
inline constexpr double kHoldTolerance = 0.3;
/// ...at this speed, m/s.
inline constexpr double kHoldSpeed = 0.5;
/// Replanning because avoidance pushed an agent off its path happens at most this often, s.
inline constexpr double kReplanInterval = 0.5;
/// A person held up until their personal space is all given up plans their way again this often, s.
inline constexpr double kStuckReplanInterval = 2.0;
/// A person pushed off their path walks on straight to their waypoint when a disc of this fraction of
/// their radius would pass; otherwise they plan again (waypoints hug the inflated walls, so the full
/// radius would fail needlessly). A robot, whose body walls stop, needs its full radius.
inline constexpr double kRejoinClearance = 0.5;
/// A person pushed off their path walks back to the corner the leg started from only from this near,
/// m; farther away they plan again. A leg's start may be where the person last arrived, metres back:
/// a pillar between them and the waypoint must not send them all the way back there.
inline constexpr double kCornerReturnReach = 1.5;
/// A robot's planner steers off the leg round people; once this far off it, whether the straight way
/// on is still free is checked again (at most every kReplanInterval), as its body walls stop, m.
inline constexpr double kRobotRejoinDistance = 0.1;
/// Without a path, planning is tried again after this long, s.
inline constexpr double kReplanRetry = 1.0;
/// A person walking to a goal who has not come this much closer to it... (m)
inline constexpr double kStuckProgress = 0.5;
/// ...for this long is stuck, s: an event says so ("stuck", once until they make progress again), so a
/// jam is seen rather than silently waited out to the time limit.
inline constexpr double kStuckTime = 10.0;
/// A person holding a motion primitive's last pose walks off it (it blends out) above this speed, m/s.
inline constexpr double kMotionReleaseSpeed = 0.2;

/// The crowd solver and its buffers, kept from tick to tick so that a tick allocates nothing; nothing
/// in them outlives a tick.
struct WalkingBuffers {
  explicit WalkingBuffers(const scenario::Model& model) : crowd(model.orca, model.social_force, model.personal_space, model.headway) {}
  humans::Crowd crowd;
  std::vector<humans::CrowdAgent> agents;
  std::vector<std::size_t> members;  ///< agent index of each crowd entry (active agents)
  std::vector<Vec2> velocities;
  std::vector<std::optional<double>> watching_headings;  ///< per agent: facing a watched robot
};

/// Standing in a robot's way (harass, HuNavSim's threatening): there within this, m...
inline constexpr double kInTheWayTolerance = 0.1;
/// ...the velocity that takes a person to the spot `distance` in front of `robot` at up to `speed`,
/// slowing over the last kArrivalSlowdown.
Vec2 into_the_way(const AgentState& self, const AgentState& robot, double distance, double speed);

/// The nearest point of the static map or of a closed door to `p`, when within `range`: the obstacle
/// people's crowd model and the robots' local planners avoid. Map points are the centres of blocked
/// cells, half a cell inside the obstacle.
std::optional<Vec2> nearest_obstacle(const scenario::Model& model, const State& state, const Vec2& p, double range);

/// Projections a walker's step gets to stand clear of the obstacles round it (each nearest one in
/// turn: a wall, then the other wall of a corner); a step still not clear after them is not taken.
inline constexpr int kClearancePasses = 3;
/// A projected centre is `radius` from the obstacle up to this rounding, m.
inline constexpr double kClearanceRounding = 1e-9;

/// Where a walker whose crowd model sends it from `from` to `to` ends: the crowd models' obstacle
/// lines and forces only discourage walking into a wall (pushed hard enough, a social-force walker
/// crossed a 0.2 m wall), so this is the hard constraint after them. Its centre stays at least
/// `radius` from the nearest obstacle point (nearest_obstacle) and inside the map by as much — or, for
/// a walker already closer, no closer than it was. A step into that margin is projected out of it
/// (sliding along the wall). `clearance` is `from`'s distance to the nearest obstacle point, or a
/// lower bound of it (the crowd model's, humans::Crowd::obstacle_distances): a step shorter than it
/// minus `radius` needs no query.
Vec2 clear_of_obstacles(const scenario::Model& model, const State& state, const Vec2& from, Vec2 to, double radius, double clearance);

/// The tick's walking phase. Robots with a model take part in the crowd but move by their own base.
void walk(const scenario::Model& model, State& state, WalkingBuffers& buffers);

/// Sends an agent to `goal` (within `radius`, then turning to its heading when `with_heading`).
void go_to(const scenario::Model& model, State& state, int agent, const Pose2& goal, double radius, bool with_heading);

/// Plans the agent's path to its goal around closed doors; false (and a retry later) without one. A
/// robot plans with its radius and kRobotPathMargin where the way is that wide, else its radius; a
/// person with their radius, else (a passage only as wide as their body) body_clearance — that first
/// when they stand in such a passage on a path that needed it.
bool plan_path(const scenario::Model& model, State& state, int agent);

/// Where a follower in a group walks: its spot in the leader's frame, facing the leader's way.
Vec2 formation_target(const State& state, int agent);

}  // namespace hrisim::sim
