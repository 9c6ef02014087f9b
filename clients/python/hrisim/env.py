"""Gymnasium-style environment over a lockstep hrisim session."""

import json
import struct

import numpy as np

from ._websocket import WebSocketError
from .client import DEFAULT_URL, Client, HrisimError

try:  # optional: Env is a gymnasium.Env and the spaces gymnasium's when it is installed
    import gymnasium as _gym
    from gymnasium import spaces as _gym_spaces
except ImportError:  # pragma: no cover - depends on the machine
    _gym = None
    _gym_spaces = None

_EnvBase = _gym.Env if _gym is not None else object

CAMERA_HEADER = struct.Struct("<4sHHqdIIffffffI36s")
assert CAMERA_HEADER.size == 96


def _number(value):
    if isinstance(value, str):
        if value in ("inf", "+inf", "Infinity"):
            return np.inf
        if value in ("-inf", "-Infinity"):
            return -np.inf
        return float(value)
    return float(value)


class Box:
    """A Gymnasium-like Box space (used when gymnasium is not installed)."""

    def __init__(self, low, high, shape=None, dtype=np.float64, seed=None):
        self.dtype = np.dtype(dtype)
        self.low = np.asarray(low, dtype=self.dtype)
        self.high = np.asarray(high, dtype=self.dtype)
        self.shape = tuple(shape) if shape is not None else self.low.shape
        self.low = np.broadcast_to(self.low, self.shape).copy()
        self.high = np.broadcast_to(self.high, self.shape).copy()
        self.np_random = np.random.default_rng(seed)

    def seed(self, seed=None):
        self.np_random = np.random.default_rng(seed)
        return [seed]

    def sample(self):
        """Uniform within finite bounds; normal where unbounded both ways, exponential where one way."""
        low, high = self.low, self.high
        lower, upper = np.isfinite(low), np.isfinite(high)
        out = np.empty(self.shape, dtype=np.float64)
        both = lower & upper
        out[both] = self.np_random.uniform(low[both], high[both])
        none = ~lower & ~upper
        out[none] = self.np_random.normal(size=int(none.sum()))
        low_only = lower & ~upper
        out[low_only] = low[low_only] + self.np_random.exponential(size=int(low_only.sum()))
        high_only = ~lower & upper
        out[high_only] = high[high_only] - self.np_random.exponential(size=int(high_only.sum()))
        return out.astype(self.dtype)

    def contains(self, x):
        try:
            x = np.asarray(x, dtype=self.dtype)
        except (TypeError, ValueError):
            return False
        return bool(x.shape == self.shape and np.all(x >= self.low) and np.all(x <= self.high))

    __contains__ = contains

    def __repr__(self):
        return "Box(%s, %s, %s, %s)" % (self.low.min(), self.high.max(), self.shape, self.dtype)

    def __eq__(self, other):
        return (isinstance(other, Box) and self.shape == other.shape and self.dtype == other.dtype
                and np.array_equal(self.low, other.low) and np.array_equal(self.high, other.high))


class Discrete:
    """A Gymnasium-like Discrete space (used when gymnasium is not installed)."""

    def __init__(self, n, seed=None):
        self.n = int(n)
        self.shape = ()
        self.dtype = np.dtype(np.int64)
        self.np_random = np.random.default_rng(seed)

    def sample(self):
        return int(self.np_random.integers(self.n))

    def contains(self, x):
        try:
            return 0 <= int(x) < self.n and int(x) == x
        except (TypeError, ValueError):
            return False

    __contains__ = contains

    def __repr__(self):
        return "Discrete(%d)" % self.n


def space_from_json(doc):
    """A space from gym-http-api's form (``{"name": "Box", "shape", "low", "high", "dtype"}``)."""
    name = doc.get("name")
    if name == "Box":
        dtype = np.dtype(doc.get("dtype", "float64"))
        shape = tuple(int(s) for s in doc["shape"])

        def bounds(values):  # one per element, or one for all of them (an image's)
            array = np.array([_number(v) for v in values], dtype=dtype)
            return np.full(shape, array[0], dtype=dtype) if array.size == 1 else array.reshape(shape)

        low, high = bounds(doc["low"]), bounds(doc["high"])
        if _gym_spaces is not None:
            return _gym_spaces.Box(low=low, high=high, shape=shape, dtype=dtype)
        return Box(low, high, shape, dtype)
    if name == "Discrete":
        if _gym_spaces is not None:
            return _gym_spaces.Discrete(int(doc["n"]))
        return Discrete(doc["n"])
    raise ValueError("unknown space %r" % name)


def decode_camera_frame(data):
    """A binary HRCF camera frame (api/asyncapi.yaml's cameraFrame) → a dict of numpy arrays."""
    if len(data) < CAMERA_HEADER.size:
        raise ValueError("camera frame of %d bytes is shorter than its header" % len(data))
    (magic, version, header_size, tick, time_, width, height, fx, fy, cx, cy, near, far, parts,
     name) = CAMERA_HEADER.unpack_from(data, 0)
    if magic != b"HRCF":
        raise ValueError("not a camera frame (magic %r)" % magic)
    if version != 1:
        raise ValueError("camera frame version %d is not supported" % version)
    w, h = width, height
    has_ids = bool(parts & 4)
    expected = header_size + w * h * (12 if has_ids else 8)
    if len(data) != expected:
        raise ValueError("camera frame of %d bytes, expected %d" % (len(data), expected))
    buf = memoryview(data)
    offset = header_size
    rgba = np.frombuffer(buf, dtype=np.uint8, count=w * h * 4, offset=offset).reshape(h, w, 4).copy()
    offset += 4 * w * h
    depth = np.frombuffer(buf, dtype="<f4", count=w * h, offset=offset).reshape(h, w).astype(np.float32)
    offset += 4 * w * h
    ids = None
    if has_ids:
        ids = np.frombuffer(buf, dtype="<u4", count=w * h, offset=offset).reshape(h, w).astype(np.uint32)
    return {
        "camera": name.split(b"\0", 1)[0].decode("utf-8", "replace"),
        "tick": tick,
        "time": time_,
        "width": w,
        "height": h,
        "fx": fx,
        "fy": fy,
        "cx": cx,
        "cy": cy,
        "near": near,
        "far": far,
        "rgba": rgba,
        "depth": depth,
        "ids": ids,
    }


def _observation(value):
    if value is None:
        return None
    return np.asarray(value, dtype=np.float64)


def image_observation(frame):
    """A decoded camera frame → the image tasks' observation: float32 H×W×5 (R, G, B, A 0–255, depth m)."""
    observation = np.empty((frame["height"], frame["width"], 5), dtype=np.float32)
    observation[..., :4] = frame["rgba"]
    observation[..., 4] = frame["depth"]
    return observation


class Env(_EnvBase):
    """A lockstep hrisim session with Gymnasium's API.

    Usually made with ``hrisim.make(scenario, ...)``; ``Env(client, session)`` wraps a session
    created elsewhere (its status, from POST /api/v1/sessions). Steps go over the session's
    WebSocket, resets over REST (the WebSocket has no reset message).
    """

    metadata = {"render_modes": []}
    render_mode = None

    def __init__(self, client, session, own_session=True):
        self.client = client
        self.session = session
        self.session_id = session["id"]
        self.scenario = session.get("scenario")
        self._own_session = own_session
        self._next_seed = None  # the next episode's seed when reset() gets none; None: the session's own
        self._ws = None
        self._closed = False
        try:
            self.action_space = space_from_json(client.action_space(self.session_id))
            observation_doc = client.observation_space(self.session_id)
            self.observation_space = space_from_json(observation_doc)
            # an image task: the observation is this camera's frame, asked for after each step
            self.observation_camera = observation_doc.get("camera")
        except BaseException:
            self.close()
            raise

    def __repr__(self):
        return "<hrisim.Env %s scenario=%s>" % (self.session_id, self.scenario)

    # -- socket ------------------------------------------------------------------------------
    @property
    def ws(self):
        if self._closed:
            raise HrisimError(None, "closed", "the environment is closed")
        if self._ws is None or self._ws.closed:
            self._ws = self.client.websocket(self.session_id)
        return self._ws

    def _ask(self, message):
        """Send a JSON message and return its answer (dict for text, bytes for binary)."""
        self._send(message)
        return self._receive()

    def _send(self, message):
        try:
            self.ws.send_json(message)
        except (OSError, WebSocketError):
            self._ws = None
            raise

    def _receive(self):
        try:
            answer = self.ws.recv()
        except (OSError, WebSocketError):
            self._ws = None
            raise
        if isinstance(answer, bytes):
            return answer
        doc = json.loads(answer)
        if doc.get("type") == "error":
            raise HrisimError.from_body(None, doc)
        return doc

    # -- Gymnasium API -----------------------------------------------------------------------
    def reset(self, *, seed=None, options=None):
        """Start the session again from tick 0 → ``(observation, info)``.

        Each episode has a seed: ``seed`` when given; without one, the session's own on the first
        reset and afterwards one drawn from the previous episode's seed, so that successive episodes
        differ (a task draws its human's place, gesture or walking style from it) and the sequence is
        the same for the same first seed, as Gymnasium's reset continues its generator.
        ``options`` as POST .../reset's: ``{"poses": {"robot": {"x", "y", "yaw"}}}``, or
        ``{"snapshot": file}`` to start the episode from a saved moment (``save_snapshot``), with the
        seed the file keeps (give no ``seed`` then).
        """
        if self._closed:
            raise HrisimError(None, "closed", "the environment is closed")
        if _gym is not None and seed is not None:
            _gym.Env.reset(self, seed=seed)
        from_snapshot = isinstance(options, dict) and "snapshot" in options
        if seed is None and not from_snapshot:
            seed = self._next_seed
        reply = self.client.reset_session(self.session_id, seed=seed, options=options)
        self._next_seed = int(np.random.default_rng(int(reply["seed"])).integers(0, 2 ** 53))
        self.last_status = reply
        info = dict(reply.get("info") or {})
        info.setdefault("tick", reply.get("tick"))
        info.setdefault("time", reply.get("time"))
        return self._observe(reply), info

    def save_snapshot(self):
        """The episode's present moment as a snapshot file (a dict): ``reset(options={"snapshot": it})``
        comes back to it, here or on another server of the same version, bit for bit."""
        taken = self.client.take_snapshot(self.session_id)
        return self.client.snapshot_file(self.session_id, taken["snapshot"])

    def _observe(self, reply):
        if self.observation_camera is None:
            return _observation(reply.get("observation"))
        self._send_observation_request()
        return self._receive_observation()

    # An image observation's two halves, so that a VectorEnv can ask every session before it reads.
    def _send_observation_request(self):
        camera = self.observation_camera
        self._send(_camera_message(camera["name"], camera["width"], camera["height"]))

    def _receive_observation(self):
        return image_observation(_camera_frame(self._receive()))

    def step(self, action, n=1):
        """Apply ``action`` and advance ``n`` steps (default 1) →
        ``(observation, reward, terminated, truncated, info)``.

        ``info`` holds the server's info plus ``events`` (those since the previous step reply) and
        ``status`` (the session's status fields).
        """
        self._send_step(action, n)
        return self._step_result(self._receive())

    # The two halves of a step, so that a VectorEnv can send to all its sessions before it reads.
    def _send_step(self, action, n=1):
        message = {"type": "step", "n": int(n)}
        if action is not None:
            message["action"] = [float(a) for a in np.asarray(action, dtype=np.float64).ravel()]
        self._send(message)

    def _step_result(self, reply, observation=None):
        """The step's answer as Gymnasium's tuple; ``observation`` when already fetched."""
        if isinstance(reply, bytes):
            raise HrisimError(None, "protocol", "binary answer to a step")
        self.last_status = reply
        info = dict(reply.get("info") or {})
        info["events"] = reply.get("events", [])
        info["status"] = {k: v for k, v in reply.items()
                          if k not in ("observation", "reward", "terminated", "truncated", "info",
                                       "events", "type")}
        if observation is None:
            observation = self._observe(reply)
        return (observation, float(reply.get("reward", 0.0)),
                bool(reply.get("terminated")), bool(reply.get("truncated")), info)

    def render(self):
        return None

    def close(self):
        """Close the WebSocket and delete the session (when this Env created it)."""
        if self._closed:
            return
        self._closed = True
        if self._ws is not None:
            try:
                self._ws.close()
            except (OSError, WebSocketError):
                pass
            self._ws = None
        if self._own_session:
            try:
                self.client.delete_session(self.session_id)
            except (HrisimError, OSError):
                pass

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        try:
            if not self._closed and self._ws is not None:
                self._ws.close()
        except Exception:
            pass

    # -- more of the session -----------------------------------------------------------------
    def camera(self, name, width=None, height=None, ids=False):
        """One camera frame of the session now (``GET …/cameras`` lists the names) → dict with
        ``rgba`` (uint8 H×W×4), ``depth`` (float32 H×W, m, 0 = nothing), ``ids`` (uint32 H×W or
        None), ``tick``, ``time``, ``width``, ``height``, ``fx``, ``fy``, ``cx``, ``cy``, ``near``,
        ``far`` and ``camera``."""
        return _camera_frame(self._ask(_camera_message(name, width, height, ids)))

    def state(self, events_since=0):
        """Every agent's pose and motion (the WebSocket's ``state``)."""
        return self._ask({"type": "state", "events_since": int(events_since)})

    def sensors(self, robot):
        return self._ask({"type": "sensors", "robot": robot})

    def commands(self, commands):
        return self._ask({"type": "commands", "commands": list(commands)})

    def metrics(self):
        return self.client.session_metrics(self.session_id)

    def cameras(self):
        return self.client.cameras(self.session_id)


def _camera_message(name, width=None, height=None, ids=False):
    message = {"type": "camera", "camera": name, "ids": bool(ids)}
    if width is not None:
        message["width"] = int(width)
    if height is not None:
        message["height"] = int(height)
    return message


def _camera_frame(reply):
    if not isinstance(reply, bytes):
        raise HrisimError(None, "protocol", "text answer %r to a camera request" % reply.get("type"))
    return decode_camera_frame(reply)


#: The HSR benchmark's tasks (seed 003 §4.4); each is a bundled scenario of the same name.
TASKS = ("approach_human", "follow_human", "approach_human_apartment", "pick_and_place",
         "mirror_gesture")


def make(scenario, url=DEFAULT_URL, seed=0, controller=None, token=None, client=None, task=None):
    """Create a lockstep session of ``scenario`` and return its ``Env``.

    ``scenario`` is a scenario id (GET /api/v1/scenarios). The benchmark tasks (``TASKS``) are
    bundled scenarios of their names: ``hrisim.make("approach_human", seed=3)`` gives that task's
    spaces, frame skip, rewards and endings. Other scenarios give the default navigation view.
    ``task`` overrides settings of the scenario's task section (docs/benchmark.md), e.g.
    ``{"frame_skip": 1, "max_episode_length": 600}``: a copy of the scenario with them is stored on
    the server first.
    """
    client = client or Client(url, token=token)
    if task:
        scenario = with_task_settings(client, scenario, task)
    session = client.create_session(scenario, seed=seed, controller=controller, mode="lockstep")
    return Env(client, session)


def with_task_settings(client, scenario, settings):
    """Stores a copy of ``scenario`` whose task section has ``settings`` → the copy's id."""
    document = client.scenario(scenario)
    if "task" not in document:
        raise ValueError("scenario %r has no task section to change" % scenario)
    document["task"].update(settings)
    document["name"] = "%s (%s)" % (document["name"], ", ".join("%s %s" % item for item in sorted(settings.items())))
    return client.upload_scenario(document)["id"]


class VectorEnv:
    """Several sessions stepped together from one client: one ``step_many`` message over the first
    session's WebSocket steps them all, the server sharing them out over its workers and answering
    once.

    Batches are numpy arrays along a first axis of ``num_envs``. A session whose episode ends is
    reset straight away (as Stable-Baselines3's vectorised environments do): its row of the
    returned observation is then the new episode's first, and its info holds ``final_observation``
    and ``final_info``.
    """

    def __init__(self, envs):
        if not envs:
            raise ValueError("a VectorEnv needs at least one environment")
        self.envs = list(envs)
        self.num_envs = len(self.envs)
        self.observation_space = self.envs[0].observation_space
        self.action_space = self.envs[0].action_space

    def reset(self, *, seed=None, options=None):
        """Resets every session (seed i + ``seed`` for the i-th when given) → ``(observations, infos)``."""
        results = [env.reset(seed=None if seed is None else seed + i, options=options)
                   for i, env in enumerate(self.envs)]
        return np.stack([r[0] for r in results]), [r[1] for r in results]

    def step(self, actions):
        """``actions``: one row per session → ``(observations, rewards, terminated, truncated, infos)``."""
        actions = np.asarray(actions, dtype=np.float64)
        if actions.shape[0] != self.num_envs:
            raise ValueError("%d actions for %d environments" % (actions.shape[0], self.num_envs))
        batch = self.envs[0]._ask({
            "type": "step_many",
            "sessions": [env.session_id for env in self.envs],
            "actions": [[float(a) for a in np.asarray(action, dtype=np.float64).ravel()] for action in actions],
        })
        replies = batch["results"]
        for reply in replies:
            if "error" in reply:
                raise HrisimError.from_body(None, reply)
        images = [None] * self.num_envs
        if self.envs[0].observation_camera is not None:  # rendered by every session at once, too
            for env in self.envs:
                env._send_observation_request()
            images = [env._receive_observation() for env in self.envs]
        results = [env._step_result(reply, image) for env, reply, image in zip(self.envs, replies, images)]
        observations, infos = [], []
        for env, (observation, _, terminated, truncated, info) in zip(self.envs, results):
            if terminated or truncated:
                info = dict(info, final_observation=observation, final_info=info)
                observation, _ = env.reset()
            observations.append(observation)
            infos.append(info)
        return (np.stack(observations), np.array([r[1] for r in results]),
                np.array([r[2] for r in results]), np.array([r[3] for r in results]), infos)

    def close(self):
        for env in self.envs:
            env.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def make_vec(scenario, num_envs, url=DEFAULT_URL, seed=0, token=None, client=None, task=None):
    """``num_envs`` sessions of ``scenario`` (seeds ``seed``, ``seed + 1``, …) as one ``VectorEnv``;
    ``task`` as ``make``'s."""
    client = client or Client(url, token=token)
    if task:
        scenario = with_task_settings(client, scenario, task)
    envs = []
    try:
        for i in range(num_envs):
            envs.append(make(scenario, seed=seed + i, client=client))
    except BaseException:
        for env in envs:
            env.close()
        raise
    return VectorEnv(envs)


def register_tasks(gymnasium_module=None):
    """Registers ``hrisim/TASK-v0`` for each of ``TASKS`` with Gymnasium (done on import when
    gymnasium is installed): ``gymnasium.make("hrisim/approach_human-v0", url=..., seed=...)``."""
    gym = gymnasium_module or _gym
    if gym is None:
        return []
    ids = []
    for task in TASKS:
        env_id = "hrisim/%s-v0" % task
        if env_id not in gym.registry:
            gym.register(id=env_id, entry_point="hrisim.env:make", kwargs={"scenario": task})
        ids.append(env_id)
    return ids


register_tasks()
