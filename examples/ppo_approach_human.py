"""PPO on an hrisim benchmark task, with the hyperparameters of seed 003's Table 5.2.

A small PPO (Schulman et al. 2017: clipped surrogate objective, GAE) written with torch alone. It
follows stable-baselines3's PPO, which the paper trained with: separate policy and value MLPs, a
diagonal Gaussian policy with a state-independent log standard deviation, actions clipped to the
action space only when sent to the environment, advantages normalised per minibatch.

Run it against a running server (``./scripts/serve``) from the repository's root:

    /usr/bin/python3 examples/ppo_approach_human.py --png docs/ppo_approach_human.png

After every rollout (``--n-steps`` environment steps) it prints the timesteps so far,
``ep_rew_mean`` and ``ep_len_mean`` (stable-baselines3's ``rollout/ep_rew_mean``: the mean return
and length of the last 100 finished episodes), the episodes finished, the wall time and the steps
per second. ``--csv`` writes those rows to a CSV file, ``--png`` plots ep_rew_mean against
timesteps (needs matplotlib).
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

# Seed 003, Table 5.2 (stable-baselines3 PPO).
TOTAL_TIMESTEPS = 50_000
N_STEPS = 1024
BATCH_SIZE = 64
LEARNING_RATE = 0.000125
GAMMA = 0.9
ENT_COEF = 7.5e-08
CLIP_RANGE = 0.3
N_EPOCHS = 5
GAE_LAMBDA = 1.0
MAX_GRAD_NORM = 0.9
VF_COEF = 0.95
HIDDEN_LAYERS = (128, 128, 128)

CSV_FIELDS = ("timesteps", "ep_rew_mean", "ep_len_mean", "episodes", "wall_seconds")
EPISODES_IN_MEAN = 100


def linear(n_in, n_out, gain):
    """A linear layer with stable-baselines3's orthogonal initialisation."""
    layer = nn.Linear(n_in, n_out)
    nn.init.orthogonal_(layer.weight, gain=gain)
    nn.init.zeros_(layer.bias)
    return layer


def mlp(n_in, n_out, output_gain):
    layers = []
    for width in HIDDEN_LAYERS:
        layers += [linear(n_in, width, gain=np.sqrt(2)), nn.ReLU()]
        n_in = width
    return nn.Sequential(*layers, linear(n_in, n_out, gain=output_gain))


class ActorCritic(nn.Module):
    def __init__(self, n_obs, n_actions):
        super().__init__()
        # Output gains as stable-baselines3's: 0.01 starts every action mean near zero.
        self.policy_net = mlp(n_obs, n_actions, output_gain=0.01)
        self.value_net = mlp(n_obs, 1, output_gain=1.0)
        self.log_std = nn.Parameter(torch.zeros(n_actions))

    def action_distribution(self, obs):
        return torch.distributions.Normal(self.policy_net(obs), self.log_std.exp())

    def value(self, obs):
        return self.value_net(obs).squeeze(-1)


def check_spaces(env):
    obs_space, action_space = env.observation_space, env.action_space
    assert getattr(obs_space, "low", None) is not None and len(obs_space.shape) == 1, (
        "PPO here needs a flat Box observation space, got %r" % (obs_space,))
    assert getattr(action_space, "low", None) is not None and len(action_space.shape) == 1, (
        "PPO here needs a flat Box action space, got %r" % (action_space,))


def as_tensor(obs):
    return torch.as_tensor(np.asarray(obs, dtype=np.float32))


def compute_advantages(rewards, values, dones, last_value):
    """GAE(gamma, lambda) advantages and returns; ``dones[t]`` ends an episode after step t."""
    advantages = torch.zeros_like(rewards)
    next_advantage, next_value = 0.0, last_value
    for t in reversed(range(len(rewards))):
        not_done = 1.0 - dones[t]
        delta = rewards[t] + GAMMA * next_value * not_done - values[t]
        next_advantage = delta + GAMMA * GAE_LAMBDA * not_done * next_advantage
        advantages[t] = next_advantage
        next_value = values[t]
    return advantages, advantages + values


def update(model, optimizer, rollout, rng):
    n = len(rollout["rewards"])
    for _ in range(N_EPOCHS):
        order = torch.as_tensor(rng.permutation(n))
        for first in range(0, n, BATCH_SIZE):
            batch = order[first:first + BATCH_SIZE]
            distribution = model.action_distribution(rollout["obs"][batch])
            log_prob = distribution.log_prob(rollout["actions"][batch]).sum(-1)
            advantages = rollout["advantages"][batch]
            if len(batch) > 1:
                advantages = (advantages - advantages.mean()) / (advantages.std() + 1e-8)
            ratio = torch.exp(log_prob - rollout["log_probs"][batch])
            clipped_ratio = torch.clamp(ratio, 1.0 - CLIP_RANGE, 1.0 + CLIP_RANGE)
            policy_loss = -torch.min(advantages * ratio, advantages * clipped_ratio).mean()
            values = model.value(rollout["obs"][batch])
            value_loss = nn.functional.mse_loss(values, rollout["returns"][batch])
            entropy = distribution.entropy().sum(-1).mean()
            loss = policy_loss - ENT_COEF * entropy + VF_COEF * value_loss
            optimizer.zero_grad()
            loss.backward()
            nn.utils.clip_grad_norm_(model.parameters(), MAX_GRAD_NORM)
            optimizer.step()


def mean_or_nan(values):
    return float(np.mean(values)) if values else float("nan")


def train(env, timesteps=TOTAL_TIMESTEPS, n_steps=N_STEPS, seed=0, log=print):
    """Train PPO on ``env`` for at least ``timesteps`` steps, in whole rollouts of ``n_steps``.

    Returns one dict per rollout with ``CSV_FIELDS``; ``ep_rew_mean`` and ``ep_len_mean`` are NaN
    until an episode has finished. The trained model is not kept: this example is about the curve.
    """
    check_spaces(env)
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    n_obs, n_actions = env.observation_space.shape[0], env.action_space.shape[0]
    action_low = np.asarray(env.action_space.low, dtype=np.float64)
    action_high = np.asarray(env.action_space.high, dtype=np.float64)
    model = ActorCritic(n_obs, n_actions)
    optimizer = torch.optim.Adam(model.parameters(), lr=LEARNING_RATE, eps=1e-5)

    obs, _ = env.reset(seed=seed)
    obs = as_tensor(obs)
    episode_return, episode_length, episodes = 0.0, 0, 0
    recent_returns = deque(maxlen=EPISODES_IN_MEAN)
    recent_lengths = deque(maxlen=EPISODES_IN_MEAN)
    steps_done, rows, start = 0, [], time.time()

    while steps_done < timesteps:
        rollout = {"obs": torch.zeros(n_steps, n_obs), "actions": torch.zeros(n_steps, n_actions),
                   "log_probs": torch.zeros(n_steps), "values": torch.zeros(n_steps),
                   "rewards": torch.zeros(n_steps), "dones": torch.zeros(n_steps)}
        for t in range(n_steps):
            with torch.no_grad():
                distribution = model.action_distribution(obs)
                action = distribution.sample()
                rollout["log_probs"][t] = distribution.log_prob(action).sum(-1)
                rollout["values"][t] = model.value(obs)
            next_obs, reward, terminated, truncated, _ = env.step(
                np.clip(action.numpy().astype(np.float64), action_low, action_high))
            episode_return += reward
            episode_length += 1
            if truncated and not terminated:
                # A time limit is not a failure: what the episode would still have earned counts.
                with torch.no_grad():
                    reward += GAMMA * float(model.value(as_tensor(next_obs)))
            rollout["obs"][t], rollout["actions"][t] = obs, action
            rollout["rewards"][t], rollout["dones"][t] = reward, float(terminated or truncated)
            if terminated or truncated:
                recent_returns.append(episode_return)
                recent_lengths.append(episode_length)
                episodes += 1
                episode_return, episode_length = 0.0, 0
                next_obs, _ = env.reset()
            obs = as_tensor(next_obs)
        steps_done += n_steps

        elapsed = time.time() - start
        row = {"timesteps": steps_done, "ep_rew_mean": mean_or_nan(recent_returns),
               "ep_len_mean": mean_or_nan(recent_lengths), "episodes": episodes,
               "wall_seconds": round(elapsed, 2)}
        rows.append(row)
        log("timesteps %7d  ep_rew_mean %9.4f  ep_len_mean %7.1f  episodes %5d  %8.1f s  %6.0f fps"
            % (steps_done, row["ep_rew_mean"], row["ep_len_mean"], episodes, elapsed,
               steps_done / elapsed))

        with torch.no_grad():
            last_value = model.value(obs)
        rollout["advantages"], rollout["returns"] = compute_advantages(
            rollout["rewards"], rollout["values"], rollout["dones"], last_value)
        update(model, optimizer, rollout, rng)
    return rows


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


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--url", default="http://127.0.0.1:8080", help="the hrisim server")
    parser.add_argument("--task", default="approach_human", help="benchmark task or scenario id")
    parser.add_argument("--timesteps", type=int, default=TOTAL_TIMESTEPS)
    parser.add_argument("--n-steps", type=int, default=N_STEPS, help="steps per rollout")
    parser.add_argument("--seed", type=int, default=0, help="seeds the session, torch and numpy")
    parser.add_argument("--torch-threads", type=int, default=1)
    parser.add_argument("--csv", metavar="PATH", help="write the per-rollout rows here")
    parser.add_argument("--png", metavar="PATH", help="plot ep_rew_mean against timesteps here")
    parser.add_argument("--token", help="API token, for a server started with --token")
    return parser.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    torch.set_num_threads(args.torch_threads)
    sys.path.insert(0, os.path.join(REPO, "clients", "python"))
    import hrisim

    with hrisim.make(args.task, url=args.url, seed=args.seed, token=args.token) as env:
        print("PPO on %s: observation %s, action %s"
              % (args.task, env.observation_space, env.action_space))
        rows = train(env, args.timesteps, n_steps=args.n_steps, seed=args.seed)
    if args.csv:
        write_csv(rows, args.csv)
        print("wrote", args.csv)
    if args.png:
        if plot_rewards(rows, args.png, "PPO on %s" % args.task):
            print("wrote", args.png)
        else:
            print("matplotlib is not installed: no plot written")


if __name__ == "__main__":
    main()
