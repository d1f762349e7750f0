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


def main(argv=None):
    args = parse_args(argv)
    torch.set_num_threads(1)
    torch.manual_seed(args.seed)
    torch.use_deterministic_algorithms(True)
    rng = np.random.default_rng(args.seed)
    log = (lambda *a, **k: None) if args.quiet else (lambda *a, **k: print(*a, **k, flush=True))

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

    N, T = args.num_envs, args.num_steps
    batch = N * T
    num_iterations = max(1, args.total_timesteps // batch)
    obs_buf = torch.zeros((T, N, obs_size))
    act_buf = torch.zeros((T, N, act_size))
    logp_buf = torch.zeros((T, N))
    val_buf = torch.zeros((T, N))
    rew_buf = np.zeros((T, N))
    term_buf = np.zeros((T, N), bool)
    trunc_buf = np.zeros((T, N), bool)
    valid_buf = np.zeros((T, N), bool)

    # reward scaling (CleanRL's NormalizeReward): the running std of the discounted return
    ret_rms = RunningMeanStd(1)
    disc_ret = np.zeros(N)

    name = args.name or f"ppo_{task.name}_seed{args.seed}"
    log(f"{name}: {N} envs x {T} steps = {batch} per iteration, {num_iterations} iterations "
        f"({num_iterations * batch} env steps), obs {obs_size}, actions {act_size}, episodes of at most "
        f"{task.max_actions} actions; success: {task.success_definition}")

    raw_obs, _ = env.reset(seed=args.seed * TRAIN_SEED_STRIDE)
    raw_obs = np.array(raw_obs)
    prev_done = np.zeros(N, bool)  # the env's episode ended in the last step: this step resets it
    ep_return = np.zeros(N)
    curve = []
    global_step = 0
    t_start = time.perf_counter()
    train_s = 0.0  # wall time of rollouts and updates, the held-out evaluations excluded
    first_target = None

    for iteration in range(1, num_iterations + 1):
        t_iter = time.perf_counter()
        if args.anneal_lr:
            optimizer.param_groups[0]["lr"] = (1.0 - (iteration - 1.0) / num_iterations) * args.learning_rate
        ended_returns, ended_success = [], []
        for t in range(T):
            agent.obs_rms.update(raw_obs)
            x = agent.obs_rms(raw_obs)
            with torch.no_grad():
                u, logp, _, value = agent.get_action_and_value(x)
            obs_buf[t], act_buf[t], logp_buf[t], val_buf[t] = x, u, logp, value.flatten()
            valid_buf[t] = ~prev_done
            next_obs, rew, term, trunc, _ = env.step(task.env_action(u.numpy()))
            next_obs, rew = np.array(next_obs), np.array(rew, np.float64)
            term, trunc = np.array(term, bool), np.array(trunc, bool)
            global_step += N
            done = term | trunc
            # reward scaling; the masked reset steps bring reward 0 and the accumulator restarts at 0
            disc_ret = disc_ret * args.gamma + rew
            if args.norm_reward:
                ret_rms.update(disc_ret[:, None])
                rew_buf[t] = np.clip(rew / np.sqrt(ret_rms.var.item() + 1e-8), -10, 10)
            else:
                rew_buf[t] = rew
            disc_ret[done] = 0.0
            term_buf[t], trunc_buf[t] = term, trunc & ~term
            ep_return += rew
            if done.any():
                ok = task.successes(next_obs, term, ep_return)
                for i in np.flatnonzero(done):
                    ended_returns.append(float(ep_return[i]))
                    ended_success.append(bool(ok[i]))
                ep_return[done] = 0.0
            prev_done = done
            raw_obs = next_obs

        # GAE: cut at every episode end; a truncation bootstraps the value of its final
        # observation, which is the next stored observation (NEXT_STEP) or raw_obs after the last step
        with torch.no_grad():
            last_value = agent.get_value(agent.obs_rms(raw_obs)).flatten().numpy()
        values = val_buf.numpy().astype(np.float64)
        next_values = np.concatenate([values[1:], last_value[None].astype(np.float64)])
        advantages = np.zeros((T, N))
        lastgaelam = np.zeros(N)
        for t in reversed(range(T)):
            ended = term_buf[t] | trunc_buf[t]
            delta = rew_buf[t] + args.gamma * next_values[t] * (~term_buf[t]) - values[t]
            lastgaelam = delta + args.gamma * args.gae_lambda * (~ended) * lastgaelam
            lastgaelam = np.where(valid_buf[t], lastgaelam, 0.0)
            advantages[t] = lastgaelam
        returns = advantages + values

        valid = valid_buf.reshape(-1)
        idx_valid = np.flatnonzero(valid)
        b_obs = obs_buf.reshape(-1, obs_size)
        b_act = act_buf.reshape(-1, act_size)
        b_logp = logp_buf.reshape(-1)
        b_adv = torch.as_tensor(advantages.reshape(-1), dtype=torch.float32)
        b_ret = torch.as_tensor(returns.reshape(-1), dtype=torch.float32)
        b_val = val_buf.reshape(-1)
        clipfracs, approx_kl = [], torch.tensor(0.0)
        for epoch in range(args.update_epochs):
            perm = idx_valid[rng.permutation(len(idx_valid))]
            for mb in np.array_split(perm, args.num_minibatches):
                mb = torch.as_tensor(mb)
                _, newlogp, entropy, newvalue = agent.get_action_and_value(b_obs[mb], b_act[mb])
                logratio = newlogp - b_logp[mb]
                ratio = logratio.exp()
                with torch.no_grad():
                    approx_kl = ((ratio - 1) - logratio).mean()
                    clipfracs.append(((ratio - 1.0).abs() > args.clip_coef).float().mean().item())
                adv = b_adv[mb]
                if args.norm_adv:
                    adv = (adv - adv.mean()) / (adv.std() + 1e-8)
                pg_loss = torch.max(-adv * ratio, -adv * ratio.clamp(1 - args.clip_coef, 1 + args.clip_coef)).mean()
                newvalue = newvalue.view(-1)
                if args.clip_vloss:
                    v_unclipped = (newvalue - b_ret[mb]) ** 2
                    v_clipped = b_val[mb] + (newvalue - b_val[mb]).clamp(-args.clip_coef, args.clip_coef)
                    v_loss = 0.5 * torch.max(v_unclipped, (v_clipped - b_ret[mb]) ** 2).mean()
                else:
                    v_loss = 0.5 * ((newvalue - b_ret[mb]) ** 2).mean()
                loss = pg_loss - args.ent_coef * entropy.mean() + v_loss * args.vf_coef
                optimizer.zero_grad()
                loss.backward()
                nn.utils.clip_grad_norm_(agent.parameters(), args.max_grad_norm)
                optimizer.step()
            if args.target_kl is not None and approx_kl > args.target_kl:
                break
        train_s += time.perf_counter() - t_iter
        iter_sps = batch / (time.perf_counter() - t_iter)

        row = {"iteration": iteration, "env_steps": global_step,
               "episodes": len(ended_returns),
               "return": float(np.mean(ended_returns)) if ended_returns else None,
               "success": float(np.mean(ended_success)) if ended_success else None,
               "v_loss": float(v_loss.item()), "pg_loss": float(pg_loss.item()),
               "approx_kl": float(approx_kl.item()), "clipfrac": float(np.mean(clipfracs)),
               "std": float(agent.actor_logstd.exp().mean().item())}
        if iteration % args.eval_every == 0 or iteration == num_iterations:
            row["heldout_return"], row["heldout_success"], heldout = evaluate(agent, eval_env, task,
                                                                              args.eval_episodes)
            if first_target is None and row["heldout_success"] >= 0.9:
                first_target = global_step
            if args.save_model:  # a checkpoint at each evaluation: a long run can be used before it ends
                torch.save(agent.state_dict(), args.save_model)
        row["wall_s"] = time.perf_counter() - t_start
        row["train_s"] = train_s
        row["sps"] = global_step / train_s
        curve.append(row)
        msg = (f"iter {iteration:4d} steps {global_step:9d}  train episodes {row['episodes']:4d} "
               f"return {row['return'] if row['return'] is not None else float('nan'):8.2f} "
               f"success {100 * (row['success'] or 0):5.1f}%  SPS {iter_sps:7.0f} (mean {row['sps']:7.0f})  "
               f"kl {row['approx_kl']:.4f} std {row['std']:.3f}  {row['wall_s']:7.1f} s")
        if "heldout_success" in row:
            msg += f"  | held-out return {row['heldout_return']:8.2f} success {100 * row['heldout_success']:5.1f}%"
        log(msg)

    env.close()
    eval_env.close()
    result = {
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
    out = pathlib.Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    (out / f"{name}.json").write_text(json.dumps(result, indent=1))
    if args.save_model:
        torch.save(agent.state_dict(), args.save_model)
    log(f"{name}: held-out success {100 * result['heldout_success']:.1f}% (return {result['heldout']['return']:.2f}) "
        f"after {global_step} env steps, {result['wall_s']:.0f} s, {result['sps']:.0f} env steps/s; "
        f"{out / (name + '.json')}")
    return result


if __name__ == "__main__":
    main()
