"""What the PPO and TD3 examples (ppo.py, td3.py) share: their command line, the environment, the
MLPs, the episode bookkeeping behind ``ep_rew_mean``, and the learning curve's CSV file and plot.

The curve is stable-baselines3's ``rollout/ep_rew_mean``, which seed 003 reports: the mean return
of the last 100 finished episodes, here one row per rollout of environment steps.
"""

import argparse
import csv
import os
import sys
import time
from collections import deque

import numpy as np
import torch
from torch import nn

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

CSV_FIELDS = ("timesteps", "ep_rew_mean", "ep_len_mean", "episodes", "wall_seconds")
EPISODES_IN_MEAN = 100


def check_spaces(env, algorithm):
    """Refuse what an MLP cannot take: both examples need flat Box observations and actions."""
    obs_space, action_space = env.observation_space, env.action_space
    if getattr(obs_space, "low", None) is None or len(obs_space.shape) != 1:
        raise ValueError("%s here needs a flat Box observation (an MLP's input), got %r; an image "
                         "task such as mirror_gesture needs a convolutional network"
                         % (algorithm, obs_space))
    if getattr(action_space, "low", None) is None or len(action_space.shape) != 1:
        raise ValueError("%s here needs a flat Box action space, got %r" % (algorithm, action_space))


def mlp(n_in, n_out, hidden_layers, orthogonal_output_gain=None):
    """A ReLU MLP. With ``orthogonal_output_gain``, stable-baselines3's actor-critic initialisation
    (orthogonal, gain √2 for hidden layers, that gain for the output, zero biases); without it,
    torch's default one, which stable-baselines3's TD3 keeps."""
    def linear(n_from, n_to, gain):
        layer = nn.Linear(n_from, n_to)
        if orthogonal_output_gain is not None:
            nn.init.orthogonal_(layer.weight, gain=gain)
            nn.init.zeros_(layer.bias)
        return layer

    layers = []
    for width in hidden_layers:
        layers += [linear(n_in, width, np.sqrt(2)), nn.ReLU()]
        n_in = width
    return nn.Sequential(*layers, linear(n_in, n_out, orthogonal_output_gain))


def as_tensor(obs):
    return torch.as_tensor(np.asarray(obs, dtype=np.float32))


def mean_or_nan(values):
    return float(np.mean(values)) if values else float("nan")


class LearningCurve:
    """Adds up each episode's return and length, and makes one row of ``CSV_FIELDS`` on ``record``.

    ``ep_rew_mean`` and ``ep_len_mean`` are NaN until an episode has finished.
    """

    def __init__(self, log=print):
        self.rows = []
        self.episodes = 0
        self._recent_returns = deque(maxlen=EPISODES_IN_MEAN)
        self._recent_lengths = deque(maxlen=EPISODES_IN_MEAN)
        self._episode_return, self._episode_length = 0.0, 0
        self._log = log
        self._start = time.time()

    def step(self, reward, episode_over):
        self._episode_return += reward
        self._episode_length += 1
        if episode_over:
            self._recent_returns.append(self._episode_return)
            self._recent_lengths.append(self._episode_length)
            self.episodes += 1
            self._episode_return, self._episode_length = 0.0, 0

    def record(self, timesteps):
        elapsed = time.time() - self._start
        row = {"timesteps": timesteps, "ep_rew_mean": mean_or_nan(self._recent_returns),
               "ep_len_mean": mean_or_nan(self._recent_lengths), "episodes": self.episodes,
               "wall_seconds": round(elapsed, 2)}
        self.rows.append(row)
        self._log("timesteps %7d  ep_rew_mean %9.4f  ep_len_mean %7.1f  episodes %5d  %8.1f s  %6.0f fps"
                  % (timesteps, row["ep_rew_mean"], row["ep_len_mean"], self.episodes, elapsed,
                     timesteps / elapsed))
        return row


def write_csv(rows, path):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=CSV_FIELDS)
        writer.writeheader()
        writer.writerows(rows)


def plot_rewards(rows, path, title):
    """Plot ep_rew_mean against timesteps to ``path``; False when matplotlib is not installed."""
    try:
        import matplotlib
    except ImportError:
        return False
    matplotlib.use("Agg")
    from matplotlib import pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4), dpi=100)
    ax.plot([r["timesteps"] for r in rows], [r["ep_rew_mean"] for r in rows], marker=".")
    ax.set_title(title)
    ax.set_xlabel("timesteps")
    ax.set_ylabel("ep_rew_mean (last %d episodes)" % EPISODES_IN_MEAN)
    ax.grid(True, alpha=0.4)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path)
    plt.close(fig)
    return True


def argument_parser(description):
    """The options both examples take; each adds its own."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--url", default="http://127.0.0.1:8080", help="the hrisim server")
    parser.add_argument("--task", default="approach_human", help="benchmark task or scenario id")
    parser.add_argument("--timesteps", type=int,
                        help="environment steps to train for (default: the seed's for the task)")
    parser.add_argument("--seed", type=int, default=0, help="seeds the session, torch and numpy")
    parser.add_argument("--torch-threads", type=int, default=1)
    parser.add_argument("--csv", metavar="PATH", help="write the learning curve's rows here")
    parser.add_argument("--png", metavar="PATH", help="plot ep_rew_mean against timesteps here")
    parser.add_argument("--token", help="API token, for a server started with --token")
    return parser


def run(args, algorithm, settings, train):
    """Train with ``train(env, settings, seed)`` on ``args.task`` and write the curve it returns."""
    torch.set_num_threads(args.torch_threads)
    sys.path.insert(0, os.path.join(REPO, "clients", "python"))
    import hrisim

    with hrisim.make(args.task, url=args.url, seed=args.seed, token=args.token) as env:
        print("%s on %s: observation %s, action %s; %s"
              % (algorithm, args.task, env.observation_space, env.action_space, settings))
        rows, _ = train(env, settings, seed=args.seed)
    if args.csv:
        write_csv(rows, args.csv)
        print("wrote", args.csv)
    if args.png:
        if plot_rewards(rows, args.png, "%s on %s" % (algorithm, args.task)):
            print("wrote", args.png)
        else:
            print("matplotlib is not installed: no plot written")
