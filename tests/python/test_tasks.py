"""The HSR benchmark's tasks from Python against a real hrisim server: the five environments, their
rewards seen from the client, the reference controllers, VectorEnv, Gymnasium registration and
2,000-step smoke runs of the PPO and TD3 examples.

    HRISIM_BINARY=build/test/server/app/hrisim python3 -m unittest tests/python/test_tasks.py -v
"""

import os
import sys
import unittest
from dataclasses import replace

from test_client import BINARY, REPO, Server

import numpy as np  # test_client has made sure numpy is there

import hrisim  # noqa: E402
from hrisim import controllers  # noqa: E402
from hrisim.controllers import run_episode  # noqa: E402

SERVER = None

# (observation shape, action shape, observation dtype) of each task (docs/benchmark.md).
SPACES = {
    "approach_human": ((11,), (2,), np.float64),
    "follow_human": ((11,), (2,), np.float64),
    "approach_human_apartment": ((11,), (2,), np.float64),
    "pick_and_place": ((18,), (8,), np.float64),
    "mirror_gesture": ((256, 256, 5), (6,), np.float32),
}


def setUpModule():
    global SERVER
    if not BINARY:
        raise unittest.SkipTest("HRISIM_BINARY is not set")
    SERVER = Server()


def tearDownModule():
    if SERVER is not None:
        SERVER.stop()


class TaskTest(unittest.TestCase):
    def make(self, task, seed=0):
        env = hrisim.make(task, url=SERVER.url, seed=seed)
        self.addCleanup(env.close)
        return env

    def test_every_task_runs_from_python_with_its_spaces(self):
        self.assertEqual(set(hrisim.TASKS), set(SPACES))
        for task, (observation_shape, action_shape, dtype) in SPACES.items():
            with self.subTest(task=task):
                env = self.make(task)
                self.assertEqual(env.observation_space.shape, observation_shape)
                self.assertEqual(env.action_space.shape, action_shape)
                observation, info = env.reset(seed=1)
                self.assertEqual(observation.shape, observation_shape)
                self.assertEqual(observation.dtype, dtype)
                self.assertEqual(info["tick"], 0)
                observation, reward, terminated, truncated, info = env.step(env.action_space.sample())
                self.assertEqual(observation.shape, observation_shape)
                self.assertIsInstance(reward, float)
                self.assertGreater(info["tick"], 0)

    def test_approach_human_rewards_add_up_to_the_distance_gained_and_end_within_30_cm(self):
        env = self.make("approach_human")
        pursuit = controllers.for_task("approach_human", env)
        reached = 0
        for seed in range(4):
            observation, _ = env.reset(seed=seed)
            start = observation[10]
            total, steps, terminated, observation, info = run_episode(env, pursuit, seed)
            # the distance terms telescope: the return is the distance gained (no collision here)
            self.assertAlmostEqual(total, start - observation[10], places=9)
            self.assertEqual(info["collision_human"], 0.0)
            if terminated:
                reached += 1
                self.assertLess(observation[10], 0.3)
            else:
                self.assertEqual(info["tick"], 1536)
        self.assertGreater(reached, 0)

    def test_same_seed_and_actions_give_the_same_episode(self):
        a, b = self.make("follow_human"), self.make("follow_human")
        for env in (a, b):
            env.reset(seed=9)
        for step in range(20):
            action = [0.2, np.sin(step)]
            oa, ra, *_ = a.step(action)
            ob, rb, *_ = b.step(action)
            np.testing.assert_array_equal(oa, ob)
            self.assertEqual(ra, rb)

    def test_mirror_gesture_observes_the_camera_and_the_reference_controller_mirrors_her(self):
        env = self.make("mirror_gesture")
        observation, _ = env.reset(seed=0)
        self.assertTrue(env.observation_space.contains(observation))
        rgba, depth = observation[..., :4], observation[..., 4]
        self.assertTrue(np.all(rgba[..., 3] == 255))
        self.assertGreater(np.count_nonzero(np.abs(depth - 2.0) < 0.3), 1000, "she stands 2 m away")
        for seed in (0, 1, 2, 3):
            total, steps, _, _, info = run_episode(env, controllers.GestureMirror(), seed)
            self.assertEqual(steps, 26)
            self.assertEqual(info["robot_points"], info["human_points"])
            self.assertGreaterEqual(total, 15)

    def test_pick_and_place_scripted_grasp_places_the_cup_in_256_ticks(self):
        env = self.make("pick_and_place")
        for seed in (0, 1, 2):
            total, steps, _, observation, info = run_episode(env, controllers.ScriptedGrasp(), seed)
            self.assertEqual(steps, 4)
            self.assertEqual(info["tick"], 256)
            self.assertLess(info["object_target_distance"], 0.05, "the cup stands on the target")
            self.assertEqual(observation[8], 0.0, "let go")
            self.assertGreater(total, 2.0)
            np.testing.assert_allclose(observation[15:18], [0.0, 0.68, 0.45])  # the target

    def test_the_apartment_planner_goes_round_the_furniture(self):
        env = self.make("approach_human_apartment")
        planner = controllers.for_task("approach_human_apartment", env)
        total, steps, terminated, observation, info = run_episode(env, planner, 0)
        self.assertTrue(terminated)
        self.assertEqual(info["touched"], [])

    def test_task_settings_can_be_changed_from_python(self):
        env = hrisim.make("approach_human", url=SERVER.url, seed=1, task={"frame_skip": 1, "max_episode_length": 5})
        self.addCleanup(env.close)
        env.reset()
        _, _, _, truncated, info = env.step([0.0, 0.0])
        self.assertEqual(info["tick"], 1, "frame skip 1")
        for _ in range(4):
            _, _, _, truncated, info = env.step([0.0, 0.0])
        self.assertTrue(truncated)
        self.assertEqual(info["tick"], 5)
        with self.assertRaises(ValueError):
            hrisim.make("elevator", url=SERVER.url, task={"frame_skip": 1})
        with self.assertRaises(hrisim.HrisimError) as raised:
            hrisim.make("approach_human", url=SERVER.url, task={"frame_skip": 0})
        self.assertIn("/task/frame_skip", str(raised.exception.details))

    def test_a_wrong_action_is_an_error_naming_it(self):
        env = self.make("pick_and_place")
        env.reset()
        with self.assertRaises(hrisim.HrisimError) as raised:
            env.step([0.1, 0.2])
        self.assertEqual(raised.exception.pointer, "/action")
        self.assertIn("expected 8 values", str(raised.exception))

    def test_vector_env_steps_sessions_together_and_resets_those_that_end(self):
        with hrisim.make_vec("approach_human", 3, url=SERVER.url, seed=2) as envs:
            observations, infos = envs.reset(seed=10)
            self.assertEqual(observations.shape, (3, 11))
            self.assertEqual(len({tuple(o[6:8]) for o in observations}), 3, "three different people")
            ended = 0
            for _ in range(160):
                observations, rewards, terminated, truncated, infos = envs.step(np.zeros((3, 2)))
                self.assertEqual(observations.shape, (3, 11))
                self.assertEqual(rewards.shape, (3,))
                for done, info, observation in zip(terminated | truncated, infos, observations):
                    if done:
                        ended += 1
                        self.assertIn("final_observation", info)
                        self.assertEqual(observation[0], 0.0, "the next episode's robot at the origin")
            self.assertEqual(ended, 3, "every standing robot runs out of time once in 160 steps")

    def test_tasks_register_with_gymnasium_when_it_is_there(self):
        class FakeGymnasium:
            def __init__(self):
                self.registry = {}

            def register(self, id, entry_point, kwargs):
                self.registry[id] = (entry_point, kwargs)

        fake = FakeGymnasium()
        ids = hrisim.register_tasks(fake)
        self.assertEqual(ids, ["hrisim/%s-v0" % task for task in hrisim.TASKS])
        self.assertEqual(fake.registry["hrisim/mirror_gesture-v0"], ("hrisim.env:make", {"scenario": "mirror_gesture"}))


class LearningSmokeTest(unittest.TestCase):
    """The examples' trainers on approach_human, for a few rollouts (examples/ppo.py, examples/td3.py)."""

    @classmethod
    def setUpClass(cls):
        try:
            import torch  # noqa: F401
        except ImportError:
            raise AssertionError("python3-torch is not installed for %s (scripts/debian-packages.txt has it)"
                                 % sys.executable)
        sys.path.insert(0, os.path.join(REPO, "examples"))

    def test_ppo_example_trains_2000_steps(self):
        import ppo

        settings = replace(ppo.settings_for("approach_human"), total_timesteps=2000, n_steps=256)
        with hrisim.make("approach_human", url=SERVER.url, seed=0) as env:
            rows, _ = ppo.train(env, settings, seed=0, log=lambda *args: None)
        self.assertEqual(len(rows), 8)
        self.assertEqual(rows[-1]["timesteps"], 2048)
        self.assertTrue(np.isfinite(rows[-1]["ep_rew_mean"]), "episodes of 154 steps have finished")

    def test_td3_example_fills_its_replay_and_updates_after_learning_starts(self):
        import td3
        import torch

        settings = replace(td3.settings_for("approach_human"), total_timesteps=2000, train_freq=256,
                           learning_starts=512, gradient_steps=10)
        with hrisim.make("approach_human", url=SERVER.url, seed=0) as env:
            rows, agent = td3.train(env, settings, seed=0, log=lambda *args: None)
        self.assertEqual([row["timesteps"] for row in rows], list(range(256, 2049, 256)))
        self.assertTrue(np.isfinite(rows[-1]["ep_rew_mean"]), "episodes of 154 steps have finished")
        self.assertEqual(agent.replay.size, 2048)
        stored = agent.replay.actions[:agent.replay.size]
        self.assertTrue(np.all(np.abs(stored) <= 1.0), "actions are stored in the actor's [-1, 1]")
        # Rounds end at 256, 512, ..., 2048: those after 512 but the last update, 10 critic steps each.
        self.assertEqual(agent.critic_updates, 5 * 10)
        self.assertEqual(agent.actor_updates, 5 * 10 // settings.policy_delay)
        trailing = [not torch.equal(online, target) for online, target
                    in zip(agent.actor.parameters(), agent.actor_target.parameters())]
        self.assertTrue(all(trailing), "the target actor trails the trained one")


if __name__ == "__main__":
    unittest.main()
