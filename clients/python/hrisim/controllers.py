"""Reference controllers for the HSR benchmark's tasks (docs/benchmark.md), and a random policy.

Each has ``reset()`` (called at the start of an episode) and ``act(observation) -> action``;
``run_episode`` runs one episode with one:

    env = hrisim.make("approach_human", url=..., seed=0)
    controller = hrisim.controllers.for_task("approach_human", env)
    episode_reward, steps, terminated, obs, info = hrisim.controllers.run_episode(env, controller, seed=3)

They read only the observation, plus the scenario's map for the apartment's path planner.
"""

import heapq
import math

import numpy as np

# Observation layout of the navigation tasks (server/tasks/navigation.hpp).
_X, _Y, _COS, _SIN, _HUMAN_X, _HUMAN_Y = 0, 1, 2, 3, 6, 7

#: Pure pursuit turns on the spot towards a target more than this far to the side, rad.
TURN_ON_THE_SPOT = 0.8
#: Yaw rate per radian of heading error while turning on the spot, 1/s.
HEADING_GAIN = 2.5
#: follow_human: the follower stops this close to the person, m (the task costs 20 below 0.1 m).
FOLLOW_DISTANCE = 0.5
#: Apartment planner: grid cell, m; cells nearer than ROBOT_RADIUS to furniture or walls are
#: forbidden, those nearer than PLANNER_CLEARANCE cost NEAR_COST times as much; lookahead, m.
PLANNER_RESOLUTION = 0.05
ROBOT_RADIUS = 0.22
PLANNER_CLEARANCE = 0.4
NEAR_COST = 5.0
LOOKAHEAD = 0.4
#: The planner's goal: the point this close to the person that is farthest from the furniture, m
#: (inside the task's 0.3 m, so that reaching it ends the episode).
GOAL_OFFSET = 0.25


def pursue(target_x, target_y, max_speed, max_turn, stop_at=0.0):
    """Pure pursuit towards a target in the robot's frame (x ahead, y left) → [v, ω]."""
    distance = math.hypot(target_x, target_y)
    angle = math.atan2(target_y, target_x)
    if abs(angle) > TURN_ON_THE_SPOT:
        return np.array([0.0, float(np.clip(HEADING_GAIN * angle, -max_turn, max_turn))])
    if distance <= stop_at:
        return np.array([0.0, 0.0])
    # the arc through the target: curvature 2 y / d²
    turn = max_speed * 2.0 * target_y / max(distance * distance, 1e-9)
    return np.array([max_speed, float(np.clip(turn, -max_turn, max_turn))])


class Pursuit:
    """approach_human and follow_human: drive straight at the person (stop short when following)."""

    def __init__(self, action_space, stop_at=0.0):
        self.max_speed = float(action_space.high[0])
        self.max_turn = float(action_space.high[1])
        self.stop_at = stop_at

    def reset(self):
        pass

    def act(self, observation):
        return pursue(observation[_HUMAN_X], observation[_HUMAN_Y], self.max_speed, self.max_turn,
                      self.stop_at)


class PlannedPursuit(Pursuit):
    """approach_human_apartment: A* on the scenario's map (GET …/world), obstacles grown by the
    clearance, then pure pursuit along the path to the person."""

    def __init__(self, action_space, world):
        super().__init__(action_space)
        (self.x0, self.y0), (x1, y1) = world["bounds"]["min"], world["bounds"]["max"]
        self.width = int(math.ceil((x1 - self.x0) / PLANNER_RESOLUTION))
        self.height = int(math.ceil((y1 - self.y0) / PLANNER_RESOLUTION))
        xs = self.x0 + (np.arange(self.width) + 0.5) * PLANNER_RESOLUTION
        ys = self.y0 + (np.arange(self.height) + 0.5) * PLANNER_RESOLUTION
        gx, gy = np.meshgrid(xs, ys)
        self.polygons = [np.asarray(obstacle["polygon"], dtype=float) for obstacle in world["obstacles"]]
        self.blocked = np.zeros(gx.shape, dtype=bool)
        near = np.zeros(gx.shape, dtype=bool)
        for polygon in self.polygons:
            self.blocked |= _near_polygon(gx, gy, polygon, ROBOT_RADIUS)
            near |= _near_polygon(gx, gy, polygon, PLANNER_CLEARANCE)
        self.cost = np.where(near, NEAR_COST, 1.0)
        self.path = []

    def goal_beside(self, human):
        """Of the points GOAL_OFFSET from the person, the one with the most room around it."""
        angles = np.linspace(-math.pi, math.pi, 32, endpoint=False)
        xs, ys = human[0] + GOAL_OFFSET * np.cos(angles), human[1] + GOAL_OFFSET * np.sin(angles)
        room = np.min([_distance_to_edges(xs, ys, polygon) for polygon in self.polygons], axis=0)
        best = int(np.argmax(room))
        return (float(xs[best]), float(ys[best]))

    def reset(self):
        self.path = []

    def _cell(self, x, y):
        return (min(max(int((y - self.y0) / PLANNER_RESOLUTION), 0), self.height - 1),
                min(max(int((x - self.x0) / PLANNER_RESOLUTION), 0), self.width - 1))

    def _point(self, cell):
        return (self.x0 + (cell[1] + 0.5) * PLANNER_RESOLUTION, self.y0 + (cell[0] + 0.5) * PLANNER_RESOLUTION)

    def plan(self, start, goal):
        """8-connected A* between two map points (their own cells count as free) → waypoints. When
        the goal cannot be reached without touching something (a person among the armchairs), the
        path goes to the reachable cell nearest to it, then straight on."""
        s, g = self._cell(*start), self._cell(*goal)
        frontier = [(0.0, s)]
        came = {s: None}
        cost = {s: 0.0}
        nearest, nearest_distance = s, math.inf
        while frontier:
            _, cell = heapq.heappop(frontier)
            if cell == g:
                break
            to_goal = math.hypot(cell[0] - g[0], cell[1] - g[1])
            if to_goal < nearest_distance:
                nearest, nearest_distance = cell, to_goal
            for dr in (-1, 0, 1):
                for dc in (-1, 0, 1):
                    nxt = (cell[0] + dr, cell[1] + dc)
                    if (dr == dc == 0 or not (0 <= nxt[0] < self.height and 0 <= nxt[1] < self.width)
                            or (self.blocked[nxt] and nxt != g)):
                        continue
                    new = cost[cell] + math.hypot(dr, dc) * self.cost[nxt]
                    if new < cost.get(nxt, math.inf):
                        cost[nxt] = new
                        came[nxt] = cell
                        heapq.heappush(frontier, (new + math.hypot(nxt[0] - g[0], nxt[1] - g[1]), nxt))
        cells = []
        cell = g if g in came else nearest
        while cell is not None:
            cells.append(cell)
            cell = came[cell]
        return [self._point(c) for c in reversed(cells)][1:] + [goal]

    def act(self, observation):
        x, y, c, s = observation[_X], observation[_Y], observation[_COS], observation[_SIN]
        hx, hy = observation[_HUMAN_X], observation[_HUMAN_Y]
        human = (x + c * hx - s * hy, y + s * hx + c * hy)
        if not self.path:
            self.path = self.plan((x, y), self.goal_beside(human))
        while len(self.path) > 1 and math.dist(self.path[0], (x, y)) < LOOKAHEAD:
            self.path.pop(0)
        tx, ty = self.path[0][0] - x, self.path[0][1] - y
        return pursue(c * tx + s * ty, -s * tx + c * ty, self.max_speed, self.max_turn)


def _distance_to_edges(px, py, polygon):
    """Distance of each point to the nearest edge of a polygon."""
    distance = np.full(np.shape(px), np.inf)
    for (ax, ay), (bx, by) in zip(polygon, np.roll(polygon, -1, axis=0)):
        ex, ey = bx - ax, by - ay
        length2 = ex * ex + ey * ey
        t = np.clip(((px - ax) * ex + (py - ay) * ey) / length2, 0.0, 1.0) if length2 > 0 else 0.0
        distance = np.minimum(distance, np.hypot(px - (ax + t * ex), py - (ay + t * ey)))
    return distance


def _near_polygon(gx, gy, polygon, clearance):
    """Grid points inside a polygon (even-odd rule) or within ``clearance`` of its edges."""
    inside = np.zeros(gx.shape, dtype=bool)
    for (ax, ay), (bx, by) in zip(polygon, np.roll(polygon, -1, axis=0)):
        crosses = (ay > gy) != (by > gy)
        with np.errstate(divide="ignore", invalid="ignore"):
            at_x = ax + (gy - ay) * (bx - ax) / (by - ay)
        inside ^= crosses & (gx < at_x)
    return inside | (_distance_to_edges(gx, gy, polygon) <= clearance)


# Arm targets [arm_lift m, arm_flex, arm_roll, wrist_flex, wrist_roll, base_roll rad] for the HSR in
# scenarios/pick_and_place.json, which starts with the arm stretched forward 16 cm above the cup and
# the hand open: the base roll joint turns the arm to the cup (0.12 rad right, where the arm's
# sideways offset puts the cup between the fingers) and to the target table on the left.
ARM_AT_CUP = [0.141, -1.5708, 0.0, 0.0, 0.0, -0.1186]
#: 1 cm higher than the grasp, so the cup does not drag on the table top on its way.
ARM_AT_TARGET = [0.151, -1.5708, 0.0, 0.0, 0.0, 1.5708 - 0.1186]


class ScriptedGrasp:
    """pick_and_place in the seed's 256 ticks (§5.3.4): down to the cup (an arm step, 120 ticks),
    close (a gripper step, 8), carry it over the target (120), open (8)."""

    def __init__(self):
        def arm(targets):
            return [-1.0, 0.0] + targets

        def gripper(close):
            return [1.0, 1.0 if close else -1.0] + [0.0] * 6

        self.script = [arm(ARM_AT_CUP), gripper(True), arm(ARM_AT_TARGET), gripper(False)]
        self.step = 0

    def reset(self):
        self.step = 0

    def act(self, observation):
        action = self.script[min(self.step, len(self.script) - 1)]
        self.step += 1
        return np.array(action)


#: mirror_gesture: she stands 2 m in front of the camera; pixels with a depth within this much of
#: that are hers (the floor there lies at her feet, below the rows looked at), m.
PERSON_DEPTH = 2.0
PERSON_DEPTH_TOLERANCE = 0.5
#: Horizontal field of view of the HSR's head camera (assets/robots/hsr.json), rad.
HEAD_CAMERA_FOV = 1.047
#: Her outstretched arm is looked for between these depths below the top of her head, m (shoulder
#: height), and farther than ARM_OFFSET from her middle (beyond her shoulders), m.
ARM_BAND = (0.2, 0.5)
ARM_OFFSET = 0.3
#: So many more pixels on one side than the other call it, as a share of the band's pixels.
POINTING_ASYMMETRY = 0.3
#: The arm's targets while no side is called yet: as the robot starts, pointing nowhere.
ARM_REST = [0.0] * 6
#: The arm stretched forward and turned by the base roll joint to the robot's left (+) or right (−).
ARM_POINT = [0.2, -1.5708, 0.0, 0.0, 0.0, 1.5708]


def pointing_side_in_image(observation):
    """'left', 'right' or None: the side of the image her outstretched arm is on, from the depth
    channel of an RGB-D observation (H×W×5). Her pixels at shoulder height, beyond her shoulders,
    are counted either side of her head; None while neither side has clearly more of them (her arms
    still down) or nobody is seen."""
    depth = observation[..., 4]
    person = np.abs(depth - PERSON_DEPTH) < PERSON_DEPTH_TOLERANCE
    rows = np.nonzero(person.any(axis=1))[0]
    if rows.size == 0:
        return None
    pixels_per_metre = observation.shape[1] / 2 / math.tan(HEAD_CAMERA_FOV / 2) / PERSON_DEPTH
    top = rows[0]
    middle = np.mean(np.nonzero(person[top: top + max(1, int(0.1 * pixels_per_metre))])[1])
    band = person[top + int(ARM_BAND[0] * pixels_per_metre): top + int(ARM_BAND[1] * pixels_per_metre)]
    columns = np.nonzero(band)[1] - middle
    reach = ARM_OFFSET * pixels_per_metre
    left, right = np.sum(columns < -reach), np.sum(columns > reach)
    if max(left, right) == 0 or abs(right - left) < POINTING_ASYMMETRY * (left + right):
        return None
    return "right" if right > left else "left"


class GestureMirror:
    """mirror_gesture: waits until her arm shows on one side of the image, then points the hand that
    way for the rest of the episode (to the robot's right when her arm is on the image's right: her
    left, as a mirror image). The side is called once: the base roll joint turns the camera too."""

    def __init__(self):
        self.side = None

    def reset(self):
        self.side = None

    def act(self, observation):
        if self.side is None:
            self.side = pointing_side_in_image(observation)
            if self.side is None:
                return np.array(ARM_REST)
        targets = list(ARM_POINT)
        if self.side == "right":
            targets[5] = -targets[5]
        return np.array(targets)


class RandomPolicy:
    """Uniform random actions within the action space's bounds (seeded)."""

    def __init__(self, action_space, seed=0):
        self.low = np.asarray(action_space.low, dtype=np.float64)
        self.high = np.asarray(action_space.high, dtype=np.float64)
        self.random = np.random.default_rng(seed)

    def reset(self):
        pass

    def act(self, observation):
        return self.random.uniform(self.low, self.high)


def run_episode(env, controller, seed=None):
    """One episode of ``env`` driven by ``controller`` → (episode reward, steps, terminated, last
    observation, last info)."""
    observation, _ = env.reset(seed=seed)
    controller.reset()
    total, steps = 0.0, 0
    while True:
        observation, reward, terminated, truncated, info = env.step(controller.act(observation))
        total += reward
        steps += 1
        if terminated or truncated:
            return total, steps, terminated, observation, info


def for_task(task, env):
    """The reference controller of a task, for an ``Env`` of it."""
    if task == "approach_human":
        return Pursuit(env.action_space)
    if task == "follow_human":
        return Pursuit(env.action_space, stop_at=FOLLOW_DISTANCE)
    if task == "approach_human_apartment":
        return PlannedPursuit(env.action_space, env.client.get("/api/v1/scenarios/%s/world" % env.scenario))
    if task == "pick_and_place":
        return ScriptedGrasp()
    if task == "mirror_gesture":
        return GestureMirror()
    raise ValueError("no reference controller for %r" % task)
