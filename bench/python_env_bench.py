"""Environment steps per second through the Python client (clients/python), for the HSR benchmark's
tasks: approach_human with a vector observation (frame skip 1 and the seed's 10) and mirror_gesture
with its 256×256 RGB-D observation, one environment and several stepped together by a VectorEnv.

    bench/python_env_bench.py URL [STEPS] [REPEATS]

against a running server (a Release build: ./scripts/serve; the VectorEnv of 16 needs 16 sessions,
`--max-sessions 16` or more). Prints one line per case: the median
steps per second of REPEATS runs of STEPS steps each (zero actions; episodes that end are reset, as
in training, and the reset counts in the time).
"""

import os
import statistics
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "clients", "python"))

import numpy as np  # noqa: E402

import hrisim  # noqa: E402


def rate(envs, steps):
    """Steps per second (environment steps: a VectorEnv of n counts n per call)."""
    action = np.zeros((envs.num_envs,) + envs.action_space.shape) if isinstance(envs, hrisim.VectorEnv) \
        else np.zeros(envs.action_space.shape)
    envs.reset(seed=0)
    calls = steps // getattr(envs, "num_envs", 1)
    started = time.perf_counter()
    for _ in range(calls):
        result = envs.step(action)
        if not isinstance(envs, hrisim.VectorEnv) and (result[2] or result[3]):
            envs.reset()
    return calls * getattr(envs, "num_envs", 1) / (time.perf_counter() - started)


def main():
    url = sys.argv[1]
    steps = int(sys.argv[2]) if len(sys.argv) > 2 else 3000
    repeats = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    client = hrisim.Client(url)
    approach_1 = hrisim.with_task_settings(client, "approach_human", {"frame_skip": 1})
    cases = [
        ("approach_human, frame skip 1, 1 env", approach_1, 1, steps),
        ("approach_human, frame skip 10, 1 env", "approach_human", 1, steps),
        ("approach_human, frame skip 1, VectorEnv of 2", approach_1, 2, steps),
        ("approach_human, frame skip 1, VectorEnv of 4", approach_1, 4, steps),
        ("approach_human, frame skip 1, VectorEnv of 16", approach_1, 16, 4 * steps),
        ("mirror_gesture, RGB-D 256x256, frame skip 10, 1 env", "mirror_gesture", 1, steps // 10),
        ("mirror_gesture, RGB-D 256x256, frame skip 10, VectorEnv of 2", "mirror_gesture", 2, steps // 10),
    ]
    for name, scenario, count, n in cases:
        if count == 1:
            envs = hrisim.make(scenario, client=client, seed=0)
        else:
            envs = hrisim.make_vec(scenario, count, client=client, seed=0)
        with envs:
            rates = [rate(envs, n) for _ in range(repeats)]
        print("%-62s %8.0f steps/s  (runs: %s)" % (name, statistics.median(rates), ", ".join("%.0f" % r for r in rates)))


if __name__ == "__main__":
    main()
