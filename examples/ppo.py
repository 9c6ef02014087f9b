"""PPO on an hrisim benchmark task, with the hyperparameters of seed 003's Tables 5.2 and 5.3.

A small PPO (Schulman et al. 2017: clipped surrogate objective, GAE) written with torch alone. It
follows stable-baselines3's PPO, which the paper trained with: separate policy and value MLPs, a
diagonal Gaussian policy with a state-independent log standard deviation, actions clipped to the
action space only when sent to the environment, advantages normalised per minibatch.

Run it against a running server (``./scripts/serve``) from the repository's root:

    /usr/bin/python3 examples/ppo.py --task follow_human --png docs/ppo_follow_human.png

After every rollout (``--n-steps`` environment steps) it prints the timesteps so far,
``ep_rew_mean`` and ``ep_len_mean`` (the mean return and length of the last 100 finished
episodes), the episodes finished, the wall time and the steps per second. ``--csv`` writes those
rows to a CSV file, ``--png`` plots ep_rew_mean against timesteps (needs matplotlib).
"""

from dataclasses import dataclass, replace

import numpy as np
import torch
from torch import nn

import training


@dataclass(frozen=True)
class PpoSettings:
    """stable-baselines3 PPO's arguments as the seed's tables give them; defaults: Table 5.2."""
    total_timesteps: int = 50_000
    n_steps: int = 1024
    batch_size: int = 64
    learning_rate: float = 0.000125
    gamma: float = 0.9
    ent_coef: float = 7.5e-08
    clip_range: float = 0.3
    n_epochs: int = 5
    gae_lambda: float = 1.0
    max_grad_norm: float = 0.9
    vf_coef: float = 0.95
    hidden_layers: tuple = (128, 128, 128)


TABLE_5_2 = PpoSettings()
# pick_and_place: n_steps 128*4*2, batch a quarter of it, more entropy, GAE's lambda below 1.
TABLE_5_3 = replace(TABLE_5_2, total_timesteps=35_000, batch_size=256, ent_coef=0.01, gae_lambda=0.95)
# The seed's §5.3.2 and §5.3.3 use §5.3.1's configuration. mirror_gesture (Table 5.4) has an image
# observation, which these MLPs do not take.
TASK_SETTINGS = {"approach_human": TABLE_5_2, "follow_human": TABLE_5_2,
                 "approach_human_apartment": TABLE_5_2, "pick_and_place": TABLE_5_3}


def settings_for(task):
    """The seed's settings for a benchmark task; Table 5.2's for any other scenario."""
    return TASK_SETTINGS.get(task, TABLE_5_2)


class ActorCritic(nn.Module):
    def __init__(self, n_obs, n_actions, hidden_layers):
        super().__init__()
        # Output gains as stable-baselines3's: 0.01 starts every action mean near zero.
        self.policy_net = training.mlp(n_obs, n_actions, hidden_layers, orthogonal_output_gain=0.01)
        self.value_net = training.mlp(n_obs, 1, hidden_layers, orthogonal_output_gain=1.0)
        self.log_std = nn.Parameter(torch.zeros(n_actions))

    def action_distribution(self, obs):
        return torch.distributions.Normal(self.policy_net(obs), self.log_std.exp())

    def value(self, obs):
        return self.value_net(obs).squeeze(-1)


def compute_advantages(rewards, values, dones, last_value, settings):
    """GAE(gamma, lambda) advantages and returns; ``dones[t]`` ends an episode after step t."""
    advantages = torch.zeros_like(rewards)
    next_advantage, next_value = 0.0, last_value
    for t in reversed(range(len(rewards))):
        not_done = 1.0 - dones[t]
        delta = rewards[t] + settings.gamma * next_value * not_done - values[t]
        next_advantage = delta + settings.gamma * settings.gae_lambda * not_done * next_advantage
        advantages[t] = next_advantage
        next_value = values[t]
    return advantages, advantages + values


def update(model, optimizer, rollout, rng, settings):
    n = len(rollout["rewards"])
    for _ in range(settings.n_epochs):
        order = torch.as_tensor(rng.permutation(n))
        for first in range(0, n, settings.batch_size):
            batch = order[first:first + settings.batch_size]
            distribution = model.action_distribution(rollout["obs"][batch])
            log_prob = distribution.log_prob(rollout["actions"][batch]).sum(-1)
            advantages = rollout["advantages"][batch]
            if len(batch) > 1:
                advantages = (advantages - advantages.mean()) / (advantages.std() + 1e-8)
            ratio = torch.exp(log_prob - rollout["log_probs"][batch])
            clipped_ratio = torch.clamp(ratio, 1.0 - settings.clip_range, 1.0 + settings.clip_range)
            policy_loss = -torch.min(advantages * ratio, advantages * clipped_ratio).mean()
            values = model.value(rollout["obs"][batch])
            value_loss = nn.functional.mse_loss(values, rollout["returns"][batch])
            entropy = distribution.entropy().sum(-1).mean()
            loss = policy_loss - settings.ent_coef * entropy + settings.vf_coef * value_loss
            optimizer.zero_grad()
            loss.backward()
            nn.utils.clip_grad_norm_(model.parameters(), settings.max_grad_norm)
            optimizer.step()


def train(env, settings=TABLE_5_2, seed=0, log=print):
    """Train PPO on ``env`` for at least ``settings.total_timesteps`` steps, in whole rollouts.

    Returns the learning curve (one dict of ``training.CSV_FIELDS`` per rollout) and the model.
    """
    training.check_spaces(env, "PPO")
    torch.manual_seed(seed)
    rng = np.random.default_rng(seed)
    n_obs, n_actions, n_steps = env.observation_space.shape[0], env.action_space.shape[0], settings.n_steps
    action_low = np.asarray(env.action_space.low, dtype=np.float64)
    action_high = np.asarray(env.action_space.high, dtype=np.float64)
    model = ActorCritic(n_obs, n_actions, settings.hidden_layers)
    optimizer = torch.optim.Adam(model.parameters(), lr=settings.learning_rate, eps=1e-5)
    curve = training.LearningCurve(log)

    obs, _ = env.reset(seed=seed)
    obs = training.as_tensor(obs)
    steps_done = 0
    while True:
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
            curve.step(reward, terminated or truncated)
            if truncated and not terminated:
                # A time limit is not a failure: what the episode would still have earned counts.
                with torch.no_grad():
                    reward += settings.gamma * float(model.value(training.as_tensor(next_obs)))
            rollout["obs"][t], rollout["actions"][t] = obs, action
            rollout["rewards"][t], rollout["dones"][t] = reward, float(terminated or truncated)
            if terminated or truncated:
                next_obs, _ = env.reset()
            obs = training.as_tensor(next_obs)
        steps_done += n_steps
        curve.record(steps_done)
        if steps_done >= settings.total_timesteps:
            return curve.rows, model  # an update after the last rollout would not show in the curve

        with torch.no_grad():
            last_value = model.value(obs)
        rollout["advantages"], rollout["returns"] = compute_advantages(
            rollout["rewards"], rollout["values"], rollout["dones"], last_value, settings)
        update(model, optimizer, rollout, rng, settings)


def main(argv=None):
    parser = training.argument_parser(__doc__.split("\n\n")[0])
    parser.add_argument("--n-steps", type=int, help="steps per rollout (default: the seed's, 1024)")
    args = parser.parse_args(argv)
    settings = settings_for(args.task)
    if args.timesteps is not None:
        settings = replace(settings, total_timesteps=args.timesteps)
    if args.n_steps is not None:
        settings = replace(settings, n_steps=args.n_steps)
    training.run(args, "PPO", settings, train)


if __name__ == "__main__":
    main()
