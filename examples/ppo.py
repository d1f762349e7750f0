#!/usr/bin/env python3
"""PPO with a Gaussian policy on a groundsim task, in one file (PyTorch and
numpy alone), after CleanRL's ppo_continuous_action.py.

    PYTHONPATH=build/python /usr/bin/python3 examples/ppo.py --task configs/tasks/goal.json --seed 0 \\
        --out-dir docs/experiments

Structure as CleanRL's: num_envs environments of one vector env (in this
process, num_threads=1), num_steps actions each per iteration, GAE, a
clipped surrogate over update_epochs passes of num_minibatches minibatches,
an optional clipped value loss, Adam with the learning rate annealed
linearly to 0, orthogonal initialisation, a 64x64 tanh actor and critic, a
state-independent log-std. Observations are normalised by their running
mean and variance (kept in the agent's state dict, so evaluation uses the
stats the policy was trained with) and clipped to [-10, 10]; rewards are
divided by the running std of the discounted return (clipped to [-10, 10]).
The network's action u is mapped to the action space affinely (u = 0 is the
centre of each component's range, u = +-1 its bounds); the environment
clips what falls outside.

Autoreset is the vector env's NEXT_STEP: the step after an episode ended
resets that env, ignores its action and returns reward 0 and the new
episode's first observation. Such a step is not a sample (its loss weight is
0, as CleanRL's EnvPool variant masks it), and the advantage recursion is
cut at every episode end. A terminated episode bootstraps nothing; a
truncated one (time limit) bootstraps the value of its final observation,
which NEXT_STEP returns at the truncation step itself (the observation the
next, masked, step is taken from).

Success:
- a task with a goal (termination.goal_radius > 0, configs/tasks/goal.json):
  the episode terminated within goal_radius of the goal (its final
  `goal_distance` observation <= goal_radius), not by tilt, leaving the
  region or divergence;
- otherwise (configs/tasks/speed.json): the episode's return reaches the
  return threshold, by default SPEED_RETURN_FRACTION (0.6) of the largest
  possible speed_tracking return (weight x the actions of a full episode,
  500 for speed.json: a threshold of 300). A per-action speed_tracking reward
  exp(-((v - target) / tolerance)^2) of 0.6 is a speed error of 0.71 x
  speed_tolerance (1.43 m/s for speed.json); the threshold asks for that on
  average over the whole episode, the acceleration from the drawn start
  speed (0 to 5 m/s) to 15 m/s included, with the jerk and effort penalties
  counted against it.

The held-out evaluation runs the mean action (deterministic) on 64 starts
drawn with reset seeds 10**9 + i, which training never uses (training env i
starts from seed seed * 2**20 + i and continues that stream), every
--eval-every iterations and after the last one.

Each iteration prints the environment steps so far, the mean return and
success of the training episodes that ended in it, and the throughput
(environment steps per second, updates included; the held-out evaluations
are not counted). The run writes <out-dir>/ppo_<task>_seed<seed>.json: the
curve (one point per iteration: env steps, wall seconds, training return
and success, held-out return and success where evaluated) and the final
held-out success. Everything is seeded (numpy, torch with deterministic
algorithms on one thread, the environments' reset seeds), so a rerun of a
seed reproduces its curve exactly; only the wall times differ."""

import argparse
import dataclasses
import json
import os
import pathlib
import platform
import sys
import time

import numpy as np
import torch
import torch.nn as nn
from torch.distributions.normal import Normal

import groundsim

ROOT = pathlib.Path(__file__).resolve().parents[1]
HELDOUT_SEED = 10**9
TRAIN_SEED_STRIDE = 2**20
SPEED_RETURN_FRACTION = 0.6


def parse_args(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--task", default=str(ROOT / "configs" / "tasks" / "goal.json"))
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--total-timesteps", type=int, default=3_000_000, help="environment steps (actions of one env)")
    p.add_argument("--num-envs", type=int, default=32)
    p.add_argument("--num-steps", type=int, default=256, help="actions per env per iteration")
    p.add_argument("--num-threads", type=int, default=1, help="threads of the vector env")
    p.add_argument("--learning-rate", type=float, default=3e-4)
    p.add_argument("--anneal-lr", type=int, default=1, help="1: anneal the learning rate linearly to 0")
    p.add_argument("--gamma", type=float, default=0.99)
    p.add_argument("--gae-lambda", type=float, default=0.95)
    p.add_argument("--num-minibatches", type=int, default=32)
    p.add_argument("--update-epochs", type=int, default=10)
    p.add_argument("--norm-adv", type=int, default=1)
    p.add_argument("--clip-coef", type=float, default=0.2)
    p.add_argument("--clip-vloss", type=int, default=1, help="1: clip the value loss as CleanRL")
    p.add_argument("--ent-coef", type=float, default=0.0)
    p.add_argument("--vf-coef", type=float, default=0.5)
    p.add_argument("--max-grad-norm", type=float, default=0.5)
    p.add_argument("--target-kl", type=float, default=None, help="stop an update's epochs beyond this KL")
    p.add_argument("--hidden", type=int, default=64, help="units of each of the two tanh layers")
    p.add_argument("--init-logstd", type=float, default=0.0)
    p.add_argument("--init-action", default=None,
                   help="comma-separated initial mean action in the env's units (e.g. 0.5,-0.5,0: half throttle, "
                        "brake released, straight); default: the centre of each component's range")
    p.add_argument("--norm-reward", type=int, default=1, help="1: scale rewards by the discounted return's std")
    p.add_argument("--success-return", type=float, default=None,
                   help="tasks without a goal: an episode succeeds at this return (default: "
                        f"{SPEED_RETURN_FRACTION} x speed_tracking weight x actions per episode)")
    p.add_argument("--eval-episodes", type=int, default=64, help="held-out starts")
    p.add_argument("--eval-every", type=int, default=10, help="iterations between held-out evaluations")
    p.add_argument("--out-dir", default="out/ppo")
    p.add_argument("--name", default=None, help="run name (default ppo_<task>_seed<seed>)")
    p.add_argument("--save-model", default=None, help="write the agent's state dict (with the obs stats) here, at each held-out "
                   "evaluation and at the end")
    p.add_argument("--quiet", action="store_true")
    return p.parse_args(argv)


class RunningMeanStd(nn.Module):
    """Running mean and variance (parallel algorithm, float64) in buffers of
    the module, so they travel with the state dict."""

    def __init__(self, size, clip=10.0):
        super().__init__()
        self.register_buffer("mean", torch.zeros(size, dtype=torch.float64))
        self.register_buffer("var", torch.ones(size, dtype=torch.float64))
        self.register_buffer("count", torch.tensor(1e-4, dtype=torch.float64))
        self.clip = clip

    def update(self, x):
        x = torch.as_tensor(np.asarray(x, np.float64))
        batch_mean, batch_var, n = x.mean(0), x.var(0, unbiased=False), x.shape[0]
        delta, total = batch_mean - self.mean, self.count + n
        m2 = self.var * self.count + batch_var * n + delta**2 * self.count * n / total
        self.mean.copy_(self.mean + delta * n / total)
        self.var.copy_(m2 / total)
        self.count.copy_(total)

    def forward(self, x):
        x = torch.as_tensor(np.asarray(x, np.float64))
        return ((x - self.mean) / torch.sqrt(self.var + 1e-8)).clamp(-self.clip, self.clip).float()


def layer_init(layer, std=np.sqrt(2), bias_const=0.0):
    torch.nn.init.orthogonal_(layer.weight, std)
    torch.nn.init.constant_(layer.bias, bias_const)
    return layer


class Agent(nn.Module):
    def __init__(self, obs_size, act_size, hidden=64, init_logstd=0.0):
        super().__init__()
        self.obs_rms = RunningMeanStd(obs_size)
        self.critic = nn.Sequential(
            layer_init(nn.Linear(obs_size, hidden)), nn.Tanh(),
            layer_init(nn.Linear(hidden, hidden)), nn.Tanh(),
            layer_init(nn.Linear(hidden, 1), std=1.0))
        self.actor_mean = nn.Sequential(
            layer_init(nn.Linear(obs_size, hidden)), nn.Tanh(),
            layer_init(nn.Linear(hidden, hidden)), nn.Tanh(),
            layer_init(nn.Linear(hidden, act_size), std=0.01))
        self.actor_logstd = nn.Parameter(torch.full((1, act_size), float(init_logstd)))

    def get_value(self, x):
        return self.critic(x)

    def get_action_and_value(self, x, action=None):
        mean = self.actor_mean(x)
        std = torch.exp(self.actor_logstd.expand_as(mean))
        probs = Normal(mean, std)
        if action is None:
            action = probs.sample()
        return action, probs.log_prob(action).sum(1), probs.entropy().sum(1), self.critic(x)


class Task:
    """What the task counts as a success, and how a network action becomes
    an environment action."""

    def __init__(self, path, layout, action_space, success_return=None):
        doc = json.loads(pathlib.Path(path).read_text())
        task = doc["task"]
        self.name = doc.get("name", pathlib.Path(path).stem)
        self.max_actions = int(np.ceil(task["time_limit"] / (layout.dt * layout.control_period) - 1e-9))
        self.goal_radius = float(task.get("termination", {}).get("goal_radius", 0.0))
        self.low = np.asarray(action_space.low, np.float32)
        self.high = np.asarray(action_space.high, np.float32)
        if self.goal_radius > 0:
            self.kind = "goal"
            self.goal_distance = list(layout.observation).index("goal_distance")
            self.success_return = None
            self.success_definition = (f"the episode terminated within goal_radius = {self.goal_radius} m of the "
                                       f"goal (final goal_distance observation <= goal_radius)")
        else:
            self.kind = "return"
            weight = float(task.get("reward", {}).get("speed_tracking", 0.0))
            if success_return is None:
                if weight <= 0:
                    raise SystemExit(f"{path}: no goal and no speed_tracking reward; give --success-return")
                success_return = SPEED_RETURN_FRACTION * weight * self.max_actions
            self.success_return = float(success_return)
            self.success_definition = (
                f"the episode's return >= {self.success_return:g} "
                f"({SPEED_RETURN_FRACTION} x speed_tracking weight {weight:g} x {self.max_actions} actions: a mean "
                f"per-action speed_tracking reward of {SPEED_RETURN_FRACTION}, i.e. a speed error of "
                f"{np.sqrt(-np.log(SPEED_RETURN_FRACTION)):.2f} x speed_tolerance on average, net of the "
                f"jerk and effort penalties)" if success_return == SPEED_RETURN_FRACTION * weight * self.max_actions
                else f"the episode's return >= {self.success_return:g} (--success-return)")

    def env_action(self, u):
        """u = 0: the centre of the range, +-1: its bounds (the env clips)."""
        return (0.5 * (self.high + self.low) + 0.5 * (self.high - self.low) * u).astype(np.float32)

    def env_u(self, a):
        """The inverse of env_action (unclipped)."""
        return ((a - 0.5 * (self.high + self.low)) / (0.5 * (self.high - self.low))).astype(np.float32)

    def successes(self, final_obs, terminated, returns):
        if self.kind == "goal":
            return terminated & (final_obs[:, self.goal_distance] <= self.goal_radius)
        return returns >= self.success_return


def blas_library():
    """The BLAS this process loaded (Debian's torch links libblas.so.3, whatever the alternatives
    system or LD_LIBRARY_PATH points it at: the reference BLAS is several times slower than
    OpenBLAS here, and the last bits of the results depend on which one ran)."""
    try:
        with open("/proc/self/maps") as f:
            paths = {line.split()[-1] for line in f if "blas" in line.lower() and "/" in line}
        return sorted(os.path.realpath(p) for p in paths)
    except OSError:
        return None


def evaluate(agent, env, task, episodes):
    """The mean action on the held-out starts (reset seeds HELDOUT_SEED + i),
    one episode each: (mean return, success rate, per-start successes)."""
    obs, _ = env.reset(seed=HELDOUT_SEED)
    obs = np.array(obs)
    returns = np.zeros(episodes)
    success = np.zeros(episodes, bool)
    running = np.ones(episodes, bool)
    for _ in range(task.max_actions + 1):
        with torch.no_grad():
            u = agent.actor_mean(agent.obs_rms(obs)).numpy()
        obs, rew, term, trunc, _ = env.step(task.env_action(u))
        obs, rew, term, trunc = np.array(obs), np.array(rew), np.array(term), np.array(trunc)
        returns += np.where(running, rew, 0.0)
        ended = running & (term | trunc)
        success |= ended & task.successes(obs, term, returns)
        running &= ~ended
        if not running.any():
            break
    return float(returns.mean()), float(success.mean()), success.astype(int).tolist()


@dataclasses.dataclass
class Rollout:
    """One iteration's samples, T steps of N envs: the normalised observations, the network actions u, their
    log-probabilities and values (torch), the scaled rewards, the terminations, the truncations that are not
    terminations, and which steps are samples (not the masked reset steps of NEXT_STEP)."""
    obs: torch.Tensor
    act: torch.Tensor
    logp: torch.Tensor
    val: torch.Tensor
    rew: np.ndarray
    term: np.ndarray
    trunc: np.ndarray
    valid: np.ndarray

    @classmethod
    def zeros(cls, T, N, obs_size, act_size):
        return cls(torch.zeros((T, N, obs_size)), torch.zeros((T, N, act_size)), torch.zeros((T, N)),
                   torch.zeros((T, N)), np.zeros((T, N)), np.zeros((T, N), bool), np.zeros((T, N), bool),
                   np.zeros((T, N), bool))


@dataclasses.dataclass
class EnvStream:
    """What the training envs carry from one rollout to the next: the last raw observation, which envs' episode
    ended in the last step (this step resets them), the episodes' returns so far, the reward scaling's discounted
    return and its running std (CleanRL's NormalizeReward), and the env steps taken."""
    raw_obs: np.ndarray
    prev_done: np.ndarray
    ep_return: np.ndarray
    disc_ret: np.ndarray
    ret_rms: RunningMeanStd
    global_step: int = 0


def seeded_rng(args):
    """torch seeded, deterministic and on one thread; the numpy generator of the minibatch permutations."""
    torch.set_num_threads(1)
    torch.manual_seed(args.seed)
    torch.use_deterministic_algorithms(True)
    return np.random.default_rng(args.seed)


def make_setup(args):
    """The training and held-out vector envs, the task, the agent (its mean action at --init-action) and Adam."""
    # the rollout below is written for NEXT_STEP autoreset: asked for explicitly, not taken as the default
    env = groundsim.make_vec(args.task, args.num_envs, args.num_threads, autoreset_mode="next_step")
    eval_env = groundsim.make_vec(args.task, args.eval_episodes, args.num_threads, autoreset_mode="next_step")
    task = Task(args.task, env.layout, env.single_action_space, args.success_return)
    obs_size, act_size = env.layout.obs_size, env.layout.action_size
    agent = Agent(obs_size, act_size, args.hidden, args.init_logstd)
    if args.init_action:
        a0 = np.array([float(v) for v in args.init_action.split(",")], np.float32)
        if a0.shape != (act_size,):
            raise SystemExit(f"--init-action: {act_size} values expected, got {args.init_action!r}")
        with torch.no_grad():  # the mean's bias: u0 with env_action(u0) = a0
            agent.actor_mean[-1].bias.copy_(torch.as_tensor(task.env_u(a0)))
    optimizer = torch.optim.Adam(agent.parameters(), lr=args.learning_rate, eps=1e-5)
    return env, eval_env, task, agent, optimizer


def start_stream(env, args):
    """The training envs reset from seed seed * TRAIN_SEED_STRIDE (env i from that + i)."""
    ret_rms = RunningMeanStd(1)
    disc_ret = np.zeros(args.num_envs)
    raw_obs, _ = env.reset(seed=args.seed * TRAIN_SEED_STRIDE)
    return EnvStream(raw_obs=np.array(raw_obs), prev_done=np.zeros(args.num_envs, bool),
                     ep_return=np.zeros(args.num_envs), disc_ret=disc_ret, ret_rms=ret_rms)


def scaled_reward(args, stream, rew, done):
    """The reward divided by the running std of the discounted return (clipped to [-10, 10]) with
    --norm-reward; the masked reset steps bring reward 0 and the accumulator restarts at 0."""
    stream.disc_ret = stream.disc_ret * args.gamma + rew
    if args.norm_reward:
        stream.ret_rms.update(stream.disc_ret[:, None])
        scaled = np.clip(rew / np.sqrt(stream.ret_rms.var.item() + 1e-8), -10, 10)
    else:
        scaled = rew
    stream.disc_ret[done] = 0.0
    return scaled


def collect_rollout(args, env, task, agent, stream, buf):
    """num_steps actions of each env into buf: the returns and successes of the training episodes that ended."""
    ended_returns, ended_success = [], []
    for t in range(args.num_steps):
        agent.obs_rms.update(stream.raw_obs)
        x = agent.obs_rms(stream.raw_obs)
        with torch.no_grad():
            u, logp, _, value = agent.get_action_and_value(x)
        buf.obs[t], buf.act[t], buf.logp[t], buf.val[t] = x, u, logp, value.flatten()
        buf.valid[t] = ~stream.prev_done
        next_obs, rew, term, trunc, _ = env.step(task.env_action(u.numpy()))
        next_obs, rew = np.array(next_obs), np.array(rew, np.float64)
        term, trunc = np.array(term, bool), np.array(trunc, bool)
        stream.global_step += args.num_envs
        done = term | trunc
        buf.rew[t] = scaled_reward(args, stream, rew, done)
        buf.term[t], buf.trunc[t] = term, trunc & ~term
        stream.ep_return += rew
        if done.any():
            ok = task.successes(next_obs, term, stream.ep_return)
            for i in np.flatnonzero(done):
                ended_returns.append(float(stream.ep_return[i]))
                ended_success.append(bool(ok[i]))
            stream.ep_return[done] = 0.0
        stream.prev_done = done
        stream.raw_obs = next_obs
    return ended_returns, ended_success


def gae(args, agent, buf, raw_obs):
    """Advantages and returns. GAE cut at every episode end; a truncation bootstraps the value of its final
    observation, which is the next stored observation (NEXT_STEP) or raw_obs after the last step."""
    with torch.no_grad():
        last_value = agent.get_value(agent.obs_rms(raw_obs)).flatten().numpy()
    values = buf.val.numpy().astype(np.float64)
    next_values = np.concatenate([values[1:], last_value[None].astype(np.float64)])
    advantages = np.zeros((args.num_steps, args.num_envs))
    lastgaelam = np.zeros(args.num_envs)
    for t in reversed(range(args.num_steps)):
        ended = buf.term[t] | buf.trunc[t]
        delta = buf.rew[t] + args.gamma * next_values[t] * (~buf.term[t]) - values[t]
        lastgaelam = delta + args.gamma * args.gae_lambda * (~ended) * lastgaelam
        lastgaelam = np.where(buf.valid[t], lastgaelam, 0.0)
        advantages[t] = lastgaelam
    return advantages, advantages + values


def minibatch_loss(args, agent, b, mb, clipfracs):
    """The clipped surrogate, the (optionally clipped) value loss and the entropy bonus of one minibatch:
    (loss, pg_loss, v_loss, approx_kl); the minibatch's clip fraction is appended to clipfracs."""
    _, newlogp, entropy, newvalue = agent.get_action_and_value(b["obs"][mb], b["act"][mb])
    logratio = newlogp - b["logp"][mb]
    ratio = logratio.exp()
    with torch.no_grad():
        approx_kl = ((ratio - 1) - logratio).mean()
        clipfracs.append(((ratio - 1.0).abs() > args.clip_coef).float().mean().item())
    adv = b["adv"][mb]
    if args.norm_adv:
        adv = (adv - adv.mean()) / (adv.std() + 1e-8)
    pg_loss = torch.max(-adv * ratio, -adv * ratio.clamp(1 - args.clip_coef, 1 + args.clip_coef)).mean()
    newvalue = newvalue.view(-1)
    if args.clip_vloss:
        v_unclipped = (newvalue - b["ret"][mb]) ** 2
        v_clipped = b["val"][mb] + (newvalue - b["val"][mb]).clamp(-args.clip_coef, args.clip_coef)
        v_loss = 0.5 * torch.max(v_unclipped, (v_clipped - b["ret"][mb]) ** 2).mean()
    else:
        v_loss = 0.5 * ((newvalue - b["ret"][mb]) ** 2).mean()
    loss = pg_loss - args.ent_coef * entropy.mean() + v_loss * args.vf_coef
    return loss, pg_loss, v_loss, approx_kl


def ppo_update(args, agent, optimizer, buf, advantages, returns, rng):
    """update_epochs passes over the samples (the valid steps) in num_minibatches minibatches, stopped early
    beyond --target-kl: the last minibatch's (pg_loss, v_loss, approx_kl) and the clip fractions."""
    idx_valid = np.flatnonzero(buf.valid.reshape(-1))
    b = {"obs": buf.obs.reshape(-1, buf.obs.shape[-1]), "act": buf.act.reshape(-1, buf.act.shape[-1]),
         "logp": buf.logp.reshape(-1), "adv": torch.as_tensor(advantages.reshape(-1), dtype=torch.float32),
         "ret": torch.as_tensor(returns.reshape(-1), dtype=torch.float32), "val": buf.val.reshape(-1)}
    clipfracs, approx_kl = [], torch.tensor(0.0)
    for epoch in range(args.update_epochs):
        perm = idx_valid[rng.permutation(len(idx_valid))]
        for mb in np.array_split(perm, args.num_minibatches):
            loss, pg_loss, v_loss, approx_kl = minibatch_loss(args, agent, b, torch.as_tensor(mb), clipfracs)
            optimizer.zero_grad()
            loss.backward()
            nn.utils.clip_grad_norm_(agent.parameters(), args.max_grad_norm)
            optimizer.step()
        if args.target_kl is not None and approx_kl > args.target_kl:
            break
    return pg_loss, v_loss, approx_kl, clipfracs


def curve_row(iteration, global_step, ended, update, agent):
    """The iteration's point of the curve: the training episodes that ended in it and the update's statistics."""
    (ended_returns, ended_success), (pg_loss, v_loss, approx_kl, clipfracs) = ended, update
    return {"iteration": iteration, "env_steps": global_step,
            "episodes": len(ended_returns),
            "return": float(np.mean(ended_returns)) if ended_returns else None,
            "success": float(np.mean(ended_success)) if ended_success else None,
            "v_loss": float(v_loss.item()), "pg_loss": float(pg_loss.item()),
            "approx_kl": float(approx_kl.item()), "clipfrac": float(np.mean(clipfracs)),
            "std": float(agent.actor_logstd.exp().mean().item())}


def heldout_point(args, agent, eval_env, task, row, global_step, first_target):
    """The held-out evaluation into row (and a checkpoint with --save-model): the per-start successes and the
    env steps of the first evaluation at 90% held-out success."""
    row["heldout_return"], row["heldout_success"], heldout = evaluate(agent, eval_env, task, args.eval_episodes)
    if first_target is None and row["heldout_success"] >= 0.9:
        first_target = global_step
    if args.save_model:  # a checkpoint at each evaluation: a long run can be used before it ends
        torch.save(agent.state_dict(), args.save_model)
    return heldout, first_target


def iteration_line(row, iter_sps):
    msg = (f"iter {row['iteration']:4d} steps {row['env_steps']:9d}  train episodes {row['episodes']:4d} "
           f"return {row['return'] if row['return'] is not None else float('nan'):8.2f} "
           f"success {100 * (row['success'] or 0):5.1f}%  SPS {iter_sps:7.0f} (mean {row['sps']:7.0f})  "
           f"kl {row['approx_kl']:.4f} std {row['std']:.3f}  {row['wall_s']:7.1f} s")
    if "heldout_success" in row:
        msg += f"  | held-out return {row['heldout_return']:8.2f} success {100 * row['heldout_success']:5.1f}%"
    return msg


def result_json(args, argv, name, task, curve, heldout, global_step, first_target, train_s):
    """The run's results: the task, the command, the final held-out evaluation, the throughput, the machine
    and the curve."""
    return {
        "name": name, "task": task.name, "task_file": os.path.relpath(args.task, ROOT) if
        os.path.isabs(args.task) else args.task, "seed": args.seed,
        "command": "PYTHONPATH=build/python /usr/bin/python3 examples/ppo.py " + " ".join(
            sys.argv[1:] if argv is None else argv),
        "args": vars(args),
        "success_definition": task.success_definition, "success_return": task.success_return,
        "heldout": {"episodes": args.eval_episodes, "reset_seeds": f"{HELDOUT_SEED} + i",
                    "policy": "mean action", "success": curve[-1]["heldout_success"],
                    "return": curve[-1]["heldout_return"], "per_start": heldout},
        "heldout_success": curve[-1]["heldout_success"],
        "env_steps": global_step, "env_steps_to_90pct_heldout": first_target,
        "wall_s": curve[-1]["wall_s"], "train_s": train_s, "sps": global_step / train_s,
        "hardware": f"{platform.machine()}, {os.cpu_count()} cores shared with other work; torch "
                    f"{torch.__version__} on 1 thread, vector env on {args.num_threads}",
        "blas": blas_library(),
        "curve": curve,
    }


def main(argv=None):
    args = parse_args(argv)
    if args.save_model:  # checkpoints are written from the first evaluation on: their folder must exist
        pathlib.Path(args.save_model).parent.mkdir(parents=True, exist_ok=True)
    rng = seeded_rng(args)
    log = (lambda *a, **k: None) if args.quiet else (lambda *a, **k: print(*a, **k, flush=True))
    env, eval_env, task, agent, optimizer = make_setup(args)
    obs_size, act_size = env.layout.obs_size, env.layout.action_size
    N, T = args.num_envs, args.num_steps
    batch = N * T
    num_iterations = max(1, args.total_timesteps // batch)
    buf = Rollout.zeros(T, N, obs_size, act_size)
    name = args.name or f"ppo_{task.name}_seed{args.seed}"
    log(f"{name}: {N} envs x {T} steps = {batch} per iteration, {num_iterations} iterations "
        f"({num_iterations * batch} env steps), obs {obs_size}, actions {act_size}, episodes of at most "
        f"{task.max_actions} actions; success: {task.success_definition}")

    stream = start_stream(env, args)
    curve, heldout, first_target = [], None, None
    t_start = time.perf_counter()
    train_s = 0.0  # wall time of rollouts and updates, the held-out evaluations excluded
    for iteration in range(1, num_iterations + 1):
        t_iter = time.perf_counter()
        if args.anneal_lr:
            optimizer.param_groups[0]["lr"] = (1.0 - (iteration - 1.0) / num_iterations) * args.learning_rate
        ended = collect_rollout(args, env, task, agent, stream, buf)
        advantages, returns = gae(args, agent, buf, stream.raw_obs)
        update = ppo_update(args, agent, optimizer, buf, advantages, returns, rng)
        train_s += time.perf_counter() - t_iter
        iter_sps = batch / (time.perf_counter() - t_iter)
        row = curve_row(iteration, stream.global_step, ended, update, agent)
        if iteration % args.eval_every == 0 or iteration == num_iterations:
            heldout, first_target = heldout_point(args, agent, eval_env, task, row, stream.global_step,
                                                  first_target)
        row["wall_s"] = time.perf_counter() - t_start
        row["train_s"] = train_s
        row["sps"] = stream.global_step / train_s
        curve.append(row)
        log(iteration_line(row, iter_sps))

    env.close()
    eval_env.close()
    result = result_json(args, argv, name, task, curve, heldout, stream.global_step, first_target, train_s)
    out = pathlib.Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{name}.json").write_text(json.dumps(result, indent=1))
    if args.save_model:
        torch.save(agent.state_dict(), args.save_model)
    log(f"{name}: held-out success {100 * result['heldout_success']:.1f}% (return {result['heldout']['return']:.2f}) "
        f"after {stream.global_step} env steps, {result['wall_s']:.0f} s, {result['sps']:.0f} env steps/s; "
        f"{out / (name + '.json')}")
    return result


if __name__ == "__main__":
    main()
