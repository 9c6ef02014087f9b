"""Reference results of the HSR benchmark (docs/benchmark.md): each task's scripted controller and a
random policy, over the same seeded episodes.

    ./scripts/serve &            # or any running hrisim server
    /usr/bin/python3 examples/baselines.py --episodes 50

Prints a Markdown table: mean episode reward (the sum of the step rewards) with its standard
deviation, mean episode length in steps, and each task's own measure of success.
"""

import argparse
import os
import statistics
import sys
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "clients", "python"))

import hrisim  # noqa: E402
from hrisim import controllers  # noqa: E402


def success(task, terminated, info):
    """The task's own measure: the person reached, the cup held or on the target, the side mirrored."""
    if task in ("approach_human", "approach_human_apartment"):
        return terminated
    if task == "follow_human":
        return info.get("distance", 99) < 1.0
    if task == "pick_and_place":
        return info.get("object_target_distance", 99) < 0.05
    return info.get("robot_points") == info.get("human_points")


def run_episodes(env, task, controller, episodes):
    returns, lengths, successes = [], [], []
    for episode in range(episodes):
        total, steps, terminated, _, info = controllers.run_episode(env, controller, seed=episode)
        returns.append(total)
        lengths.append(steps)
        successes.append(bool(success(task, terminated, info)))
    return returns, lengths, successes


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--url", default="http://127.0.0.1:8080")
    parser.add_argument("--token")
    parser.add_argument("--episodes", type=int, default=50)
    parser.add_argument("--tasks", nargs="*", default=list(hrisim.TASKS))
    args = parser.parse_args(argv)

    client = hrisim.Client(args.url, token=args.token)
    rows = []
    # (label, task, scenario id)
    cases = [(task, task, task) for task in args.tasks]
    for label, task, scenario in cases:
        with hrisim.make(scenario, seed=0, client=client) as env:
            for name, controller in (("scripted", controllers.for_task(task, env)),
                                     ("random", controllers.RandomPolicy(env.action_space, seed=0))):
                started = time.monotonic()
                returns, lengths, successes = run_episodes(env, task, controller, args.episodes)
                rows.append((label, name, statistics.mean(returns), statistics.pstdev(returns),
                             statistics.mean(lengths), sum(successes) / len(successes), time.monotonic() - started))
                print("%s %s: %.3f ± %.3f, %.1f steps, success %.0f %%, %.1f s" % (
                    label, name, rows[-1][2], rows[-1][3], rows[-1][4], 100 * rows[-1][5], rows[-1][6]), file=sys.stderr)
    print("| task | controller | mean episode reward (± sd) | mean steps | success |")
    print("|---|---|---|---|---|")
    for task, name, mean, sd, steps, rate, _ in rows:
        print("| %s | %s | %.3f ± %.3f | %.1f | %.0f %% |" % (task, name, mean, sd, steps, 100 * rate))


if __name__ == "__main__":
    main()
