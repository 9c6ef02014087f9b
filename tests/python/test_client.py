"""Tests of the Python client (clients/python/hrisim) against a real hrisim server.

    HRISIM_BINARY=build/test/server/app/hrisim python3 -m unittest discover -s tests/python -v

The server is started once for the module on a free loopback port and stopped at the end; a
second one with --token runs for the token test only. Without HRISIM_BINARY the tests are skipped.
"""

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import unittest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "clients", "python"))

try:
    import numpy as np
except ImportError:  # e.g. a python3 other than Debian's, which has python3-numpy
    if os.environ.get("HRISIM_BINARY"):
        raise  # asked to test a server (ctest does): a missing numpy fails rather than skips
    raise unittest.SkipTest("numpy is not installed for %s" % sys.executable)

import hrisim  # noqa: E402
from hrisim._websocket import WebSocketClosed  # noqa: E402

BINARY = os.environ.get("HRISIM_BINARY")
LISTENING = re.compile(r"listening on (http://127\.0\.0\.1:\d+)")


class Server:
    """An hrisim server on a free loopback port, with its database in a scratch folder."""

    def __init__(self, *extra):
        self.dir = tempfile.mkdtemp(prefix="hrisim-py-")
        env = dict(os.environ, HRISIM_SCENARIOS=os.path.join(REPO, "scenarios"))
        env.pop("HRISIM_TOKEN", None)
        self.output = []
        self.proc = subprocess.Popen(
            [BINARY, "serve", "--host", "127.0.0.1", "--port", "0",
             "--db", os.path.join(self.dir, "hrisim.db"), "--log-requests", "0", *extra],
            cwd=REPO, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.url = None
        found = threading.Event()

        def read():
            for line in self.proc.stdout:
                self.output.append(line)
                match = LISTENING.search(line)
                if match and not found.is_set():
                    self.url = match.group(1)
                    found.set()
            found.set()

        self.reader = threading.Thread(target=read, daemon=True)
        self.reader.start()
        if not found.wait(20) or self.url is None:
            self.stop()
            raise RuntimeError("hrisim did not start:\n" + "".join(self.output))

    def stop(self):
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
            try:
                self.proc.wait(15)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        self.reader.join(5)
        self.proc.stdout.close()
        shutil.rmtree(self.dir, ignore_errors=True)


SERVER = None


def setUpModule():
    global SERVER
    if not BINARY:
        raise unittest.SkipTest("HRISIM_BINARY is not set")
    SERVER = Server()


def tearDownModule():
    if SERVER is not None:
        SERVER.stop()


class EnvTest(unittest.TestCase):
    def make(self, seed=0):
        env = hrisim.make("elevator", url=SERVER.url, seed=seed)
        self.addCleanup(env.close)
        return env

    def test_spaces_have_the_documented_shapes(self):
        env = self.make()
        self.assertEqual(env.observation_space.shape, (48,))
        self.assertEqual(env.observation_space.dtype, np.float64)
        self.assertEqual(env.action_space.shape, (2,))
        self.assertEqual(env.action_space.low.shape, (2,))
        self.assertTrue(np.all(env.action_space.low < env.action_space.high))
        # people's velocities are unbounded: "inf" became infinities
        self.assertTrue(np.isinf(env.observation_space.high).any())
        self.assertTrue(env.action_space.contains(env.action_space.sample()))

    def test_reset_gives_an_observation_in_the_space_and_equal_ones_for_equal_seeds(self):
        env = self.make()
        obs, info = env.reset(seed=5)
        self.assertIsInstance(obs, np.ndarray)
        self.assertEqual(obs.dtype, np.float64)
        self.assertEqual(obs.shape, (48,))
        self.assertTrue(env.observation_space.contains(obs))
        self.assertEqual(info["tick"], 0)
        env.step([0.2, 0.1])
        again, _ = env.reset(seed=5)
        np.testing.assert_array_equal(obs, again)

    def test_stepping_with_an_action_moves_the_robot(self):
        env = self.make()
        obs, _ = env.reset()
        x0 = obs[0]
        for _ in range(60):
            obs, reward, terminated, truncated, info = env.step([0.2, 0.0])
        self.assertNotAlmostEqual(obs[0], x0, places=3)
        self.assertIsInstance(reward, float)
        self.assertFalse(terminated)
        self.assertFalse(truncated)
        self.assertEqual(info["tick"], 60)
        self.assertIn("events", info)

    def test_two_envs_with_the_same_seed_and_actions_agree(self):
        a, b = self.make(seed=11), self.make(seed=11)
        oa, _ = a.reset()
        ob, _ = b.reset()
        np.testing.assert_array_equal(oa, ob)
        rng = np.random.default_rng(0)
        for _ in range(40):
            action = a.action_space.low + rng.random(2) * (a.action_space.high - a.action_space.low)
            oa = a.step(action)[0]
            ob = b.step(action)[0]
            np.testing.assert_array_equal(oa, ob)

    def test_reset_from_a_saved_snapshot_comes_back_to_that_moment_in_another_env(self):
        env = self.make(seed=3)
        env.reset()
        for _ in range(30):
            env.step([0.2, 0.1])
        saved = json.loads(json.dumps(env.save_snapshot()))  # as a file keeps it
        later = [env.step([0.1, -0.1])[0] for _ in range(10)]
        other = self.make(seed=99)
        obs, info = other.reset(options={"snapshot": saved})
        self.assertEqual(info["tick"], saved["tick"])
        self.assertEqual(other.last_status["seed"], 3)
        again = [other.step([0.1, -0.1])[0] for _ in range(10)]
        np.testing.assert_array_equal(np.array(later), np.array(again))
        with self.assertRaises(hrisim.HrisimError) as caught:
            other.reset(seed=1, options={"snapshot": saved})
        self.assertEqual(caught.exception.details.get("pointer"), "/seed")

    def test_a_wrong_action_length_is_an_error_naming_the_action(self):
        env = self.make()
        env.reset()
        with self.assertRaises(hrisim.HrisimError) as caught:
            env.step([0.1, 0.2, 0.3])
        self.assertEqual(caught.exception.code, "bad_request")
        self.assertEqual(caught.exception.details.get("pointer"), "/action")
        # the socket stays usable after an error answer
        obs = env.step([0.0, 0.0])[0]
        self.assertEqual(obs.shape, (48,))

    def test_camera_frame(self):
        env = self.make()
        env.reset()
        env.step([0.0, 0.0])
        frame = env.camera("robot.head_rgbd", 64, 48, ids=True)
        self.assertEqual(frame["rgba"].shape, (48, 64, 4))
        self.assertEqual(frame["rgba"].dtype, np.uint8)
        self.assertEqual(frame["depth"].shape, (48, 64))
        self.assertEqual(frame["depth"].dtype, np.float32)
        self.assertEqual(frame["ids"].shape, (48, 64))
        self.assertEqual(frame["ids"].dtype, np.uint32)
        self.assertTrue((frame["depth"] > 0).any())
        self.assertEqual(frame["tick"], 1)
        self.assertEqual(frame["camera"], "robot.head_rgbd")
        self.assertGreater(frame["fx"], 0)
        plain = env.camera("robot.head_rgbd", 32, 24)
        self.assertIsNone(plain["ids"])
        self.assertEqual(plain["rgba"].shape, (24, 32, 4))
        with self.assertRaises(hrisim.HrisimError) as caught:
            env.camera("no_such_camera")
        self.assertEqual(caught.exception.code, "not_found")

    def test_a_session_deleted_elsewhere_closes_its_socket_with_the_reason(self):
        env = self.make()
        env.reset()
        env.step([0.0, 0.0])
        hrisim.Client(SERVER.url).delete_session(env.session_id)
        with self.assertRaises(WebSocketClosed) as caught:
            for _ in range(2):  # a message the server was already waiting for is answered first
                with self.assertRaises(hrisim.HrisimError) as answer:
                    env.step([0.0, 0.0])
                self.assertEqual(answer.exception.code, "not_found")
        self.assertEqual(caught.exception.code, 1000)
        self.assertEqual(caught.exception.reason, "session %s ended" % env.session_id)

    def test_close_deletes_the_session(self):
        env = hrisim.make("elevator", url=SERVER.url)
        env.reset()
        env.step([0.0, 0.0])
        env.close()
        with self.assertRaises(hrisim.HrisimError) as caught:
            env.client.session(env.session_id)
        self.assertEqual(caught.exception.status, 404)


class ClientTest(unittest.TestCase):
    def setUp(self):
        self.client = hrisim.Client(SERVER.url)

    def test_scenarios(self):
        ids = [s["id"] for s in self.client.scenarios()]
        self.assertIn("elevator", ids)
        self.assertIn("queue", ids)
        self.assertIn("steps", self.client.scenario("queue"))
        with self.assertRaises(hrisim.HrisimError) as caught:
            self.client.scenario("no_such_scenario")
        self.assertEqual(caught.exception.status, 404)
        self.assertEqual(caught.exception.code, "not_found")

    def test_a_scenario_uploaded_with_its_map(self):
        pgm = b"P5\n20 10\n255\n" + bytes([254] * 200)
        document = {"name": "mapped", "world": {"map": "lab.yaml"},
                    "humans": [{"id": "ana", "start": {"x": 1.0, "y": 0.5, "theta": 0.0}}], "steps": []}
        yaml = "image: lab.pgm\nresolution: 0.1\norigin: [0.0, 0.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
        summary = self.client.upload_scenario(document, files={"lab.yaml": yaml, "lab.pgm": pgm})
        self.assertEqual(summary["origin"], "uploaded")
        with self.assertRaises(hrisim.HrisimError) as caught:
            self.client.upload_scenario(document)
        self.assertEqual(caught.exception.status, 400, "without its files the map is not found")

    def test_unknown_scenario_for_a_session(self):
        with self.assertRaises(hrisim.HrisimError) as caught:
            hrisim.make("no_such_scenario", url=SERVER.url)
        self.assertEqual(caught.exception.status, 404)

    def test_runs(self):
        report = self.client.start_run("queue", seeds=[1, 2], max_time=10)
        run_id = report["id"]
        done = self.client.wait_run(run_id, timeout=60)
        self.assertEqual(done["status"], "finished")
        episodes = self.client.episodes(run_id)
        self.assertEqual(len(episodes), 2)
        self.assertEqual(sorted(e["seed"] for e in episodes), [1, 2])
        self.assertIn("metrics", episodes[0])
        episode = self.client.episode(episodes[0]["id"])
        self.assertIn("metrics", episode)
        trajectory = self.client.trajectory(episodes[0]["id"])
        self.assertIsInstance(trajectory, dict)
        self.assertEqual([c["name"] for c in self.client.episode_cameras(episodes[0]["id"])][:2], ["overview", "follow"])
        job = self.client.film_episode(episodes[0]["id"], fps=5, width=64)
        done = self.client.wait_video(job["id"], timeout=120)
        self.assertEqual(done["status"], "done")
        self.assertTrue(done["matches_stored_episode"])
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "episode.mp4")
            self.assertEqual(self.client.download_video(job["id"], path), done["bytes"])
            with open(path, "rb") as video:
                self.assertEqual(video.read(8)[4:], b"ftyp")
        self.client.cancel_video(job["id"])
        with self.assertRaises(hrisim.HrisimError) as gone:
            self.client.video(job["id"])
        self.assertEqual(gone.exception.status, 404)
        with self.assertRaises(hrisim.HrisimError) as wrong:
            self.client.film_episode(episodes[0]["id"], camera="ceiling")
        self.assertEqual(wrong.exception.details.get("pointer"), "/camera")

        definitions = self.client.metrics()
        keys = [m["key"] for m in definitions["items"]]
        self.assertIn("collisions", keys)
        self.assertIn(run_id, [r["id"] for r in self.client.runs()["items"]])
        comparison = self.client.compare(run_id, run_id)
        self.assertIsInstance(comparison, dict)
        with self.assertRaises(hrisim.HrisimError) as caught:
            self.client.start_run("queue", seeds=[1], gates=["collisions.median < 1"])
        self.assertEqual(caught.exception.status, 400)
        self.assertEqual(caught.exception.details.get("pointer"), "/gates/0")

    def test_a_run_from_another_machine_is_imported(self):
        scenarios = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scenarios")
        with tempfile.TemporaryDirectory() as folder:
            database = os.path.join(folder, "elsewhere.db")
            subprocess.run([BINARY, "run", os.path.join(scenarios, "queue.json"), "--seeds", "1-3", "--max-time", "2", "--name", "elsewhere",
                            "--db", database], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            imported = self.client.import_runs(database)
            self.assertEqual(len(imported), 1)
            self.assertEqual(imported[0]["added"], 3)
            self.assertEqual(self.client.run(imported[0]["id"])["name"], "elsewhere")
            self.assertEqual(self.client.import_runs(database)[0]["present"], 3)
            with open(os.path.join(folder, "text.db"), "w") as text:
                text.write("not a database")
            with self.assertRaises(hrisim.HrisimError) as refused:
                self.client.import_runs(os.path.join(folder, "text.db"))
            self.assertEqual(refused.exception.status, 400)


TOKEN = "t0123456789abcdef"  # the server wants at least 16 characters


class TokenTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server("--token", TOKEN)

    @classmethod
    def tearDownClass(cls):
        cls.server.stop()

    def test_with_the_token(self):
        with hrisim.make("elevator", url=self.server.url, token=TOKEN) as env:
            obs, _ = env.reset()
            self.assertEqual(obs.shape, (48,))
            obs = env.step([0.2, 0.0])[0]  # over a WebSocket opened with a ticket
            self.assertEqual(obs.shape, (48,))

    def test_without_the_token(self):
        with self.assertRaises(hrisim.HrisimError) as caught:
            hrisim.make("elevator", url=self.server.url)
        self.assertEqual(caught.exception.status, 401)
        self.assertEqual(caught.exception.code, "unauthorized")
        with self.assertRaises(hrisim.HrisimError) as caught:
            hrisim.Client(self.server.url, token="wrong").scenarios()
        self.assertEqual(caught.exception.status, 401)


if __name__ == "__main__":
    unittest.main()
