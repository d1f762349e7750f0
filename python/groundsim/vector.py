"""Gymnasium's vector API over a groundsim._core.BatchEnv.

The C++ environments write into the caller's numpy arrays. By default
(``copy=True``, as Gymnasium's vector envs) reset() and step() return
fresh arrays each call, which the batch wrote directly (nothing is
copied: a partial reset or a restore carries the other rows' observations
over); with ``copy=False`` they return read-only views of arrays allocated
once, overwritten by the next call (keep what you need with
``obs.copy()``). docs/experiments.md "Python" has the measured cost."""

import json
import operator
from collections.abc import Mapping

import numpy as np

from ._episodes import EpisodeStatistics, autoreset_mode_of
from ._errors import ExperimentError
from ._gym import AutoresetMode, Box, VectorEnv, batch_space
from .video import render_frames, render_options

_SEED_END = 2**63  # seeds are in [0, 2^63)


def _readonly(array):
    view = array.view()
    view.flags.writeable = False
    return view


def _index(value, field):
    try:
        return operator.index(value)
    except TypeError:
        raise ExperimentError(field, f"{field}: must be an integer, got {type(value).__name__}") from None


class VecEnv(VectorEnv):
    """num_envs environments of one scenario task, stepped together.

    Gymnasium's vector API (a gymnasium.vector.VectorEnv when gymnasium is
    importable): reset(seed, options) -> (obs, infos); step(actions) ->
    (obs, rewards, terminations, truncations, infos).

    autoreset_mode (``metadata["autoreset_mode"]``): NEXT_STEP (default) resets
    an env in the step after its episode ended, ignoring its action;
    SAME_STEP resets it in the step that ended it and puts the last
    observation in ``infos["final_obs"]`` and its infos in
    ``infos["final_info"]`` (masks ``_final_obs``, ``_final_info``);
    DISABLED never resets: step() refuses an env whose episode ended until
    reset(options={"reset_mask": ...}) resets it.

    infos: ``episode_index``, ``episode_steps``, ``episode_return``,
    ``diverged`` for every env every step (masks all true), and, in a step
    where episodes end, Gymnasium's episode statistics ``episode`` = {"r",
    "l", "t"} with the ``_episode`` mask (``episode_statistics=False`` leaves
    them to a wrapper such as gymnasium's RecordEpisodeStatistics, which
    refuses an env that already reports them).
    Curriculum: set_randomization(ranges, envs) or reset(options={"randomize":
    ranges}) change what the next resets of those envs draw; drawn() (and
    ``infos["drawn"]`` with ``drawn_in_infos=True``) is what each env's last
    reset drew, columns named by ``layout.drawn``.
    Besides: ``layout`` (component names, dt, control period, wheel counts),
    ``snapshot(env)`` and ``restore(env, data)``."""

    def __init__(self, core, name="groundsim", *, copy=True, autoreset_mode=AutoresetMode.NEXT_STEP,
                 episode_statistics=True, drawn_in_infos=False, render_mode=None, render_size=(128, 96)):
        mode = autoreset_mode_of(autoreset_mode)
        self._core = core
        self._name = name
        self._copy = bool(copy)
        self._mode = mode
        layout = core.layout
        # one row per agent of each environment ("world"): Gymnasium's num_envs is the rows
        n, obs_size, action_size = layout.rows, layout.obs_size, layout.action_size
        self.num_envs = n
        self.num_worlds = layout.num_envs
        self.num_agents = layout.num_agents
        self.render_mode, self._render_size = render_options(render_mode, render_size)
        control_dt = core.layout.dt * core.layout.control_period
        self.metadata = {"autoreset_mode": mode, "render_modes": ["rgb_array"], "render_fps": 1.0 / control_dt}
        self.spec = None
        self.closed = False
        self.single_observation_space = Box(np.asarray(layout.observation_low, np.float32),
                                            np.asarray(layout.observation_high, np.float32), dtype=np.float32)
        self.single_action_space = Box(np.asarray(layout.action_low, np.float32),
                                       np.asarray(layout.action_high, np.float32), dtype=np.float32)
        self.observation_space = batch_space(self.single_observation_space, n)
        self.action_space = batch_space(self.single_action_space, n)
        self._action_shape = (n, action_size)

        # the buffers the C++ side writes (copy=True: new ones each call, _fresh),
        # and read-only views of them for the caller (copy=False)
        self._obs = np.zeros((n, obs_size), np.float32)
        self._rewards = np.zeros(n, np.float64)
        self._terminations = np.zeros(n, np.bool_)
        self._truncations = np.zeros(n, np.bool_)
        self._info_arrays = {"episode_index": np.zeros(n, np.int64), "episode_steps": np.zeros(n, np.int64),
                             "episode_return": np.zeros(n, np.float64), "diverged": np.zeros(n, np.bool_)}
        # several agents: whether each row's agent took part in the last step (a finished one waits
        # for its world's episode to end)
        self._active = np.ones(n, np.bool_) if self.num_agents > 1 else None
        self._stats = EpisodeStatistics(n) if episode_statistics else None
        self._drawn = np.zeros((self.num_worlds, len(layout.drawn)), np.float64) if drawn_in_infos else None
        self._ended = np.zeros(n, np.bool_)  # DISABLED: episodes ended and not reset since
        self._views = tuple(_readonly(a) for a in (self._obs, self._rewards, self._terminations, self._truncations))
        # every env reports every key on every step: Gymnasium's "_key" masks are all true
        self._everyone = np.ones(n, np.bool_)  # copied for copy=True's masks (cheaper than np.ones)
        everyone = _readonly(self._everyone)
        self._infos = {}
        for key, array in self._info_arrays.items():
            self._infos[key] = _readonly(array)
            self._infos["_" + key] = everyone

    @property
    def layout(self):
        """Names of the observation and action components, dt, control
        period, time limit, wheels per vehicle (a groundsim._core.Layout)."""
        return self._core.layout

    def reset(self, *, seed=None, options=None):
        """Resets every env, or those chosen by options.

        seed: None (each env continues its own random stream), an int s
        (env i is seeded with s + i, also in a partial reset, so resetting
        env i alone gives the same state as a full reset), or a sequence of
        num_envs ints or Nones (env i gets seed[i]).
        options: None, {"env": i or [i, ...]} or Gymnasium's
        {"reset_mask": bool array of shape (num_envs,)}; the others keep
        their state. Returns every env's observation."""
        rows = self._envs_to_reset(options)
        worlds = None if rows is None else self._worlds_of(rows, "options")
        seeds = self._seeds(seed)
        if options is not None and "randomize" in options:
            self.set_randomization(options["randomize"], worlds)
        self._fresh(keep_obs=worlds is not None)
        if worlds is None and not isinstance(seeds, list):
            self._core.reset(seeds, self._obs)
        else:
            for w in range(self.num_worlds) if worlds is None else worlds:
                self._core.reset_env(w, seeds[w] if isinstance(seeds, list) else
                                     (None if seeds is None else seeds + w), self._obs)
        self._fill_infos()
        chosen = slice(None) if worlds is None else self._rows(worlds)
        self._ended[chosen] = False
        if self._stats is not None:
            self._stats.started(chosen)
        return self._out(0), self._infos_out()

    def step(self, actions):
        """actions: array-like of shape (num_envs, action_size), cast to
        float32; NaN or inf is refused (ExperimentError, field
        "actions[i][j]"), finite values are clipped to the action space.
        What happens to an env whose episode ended depends on the
        autoreset mode (class docstring)."""
        if isinstance(actions, np.ndarray) and actions.dtype == np.float32:
            a = actions
        else:
            try:
                # a value beyond float32's range becomes inf and is refused below
                with np.errstate(over="ignore"):
                    a = np.asarray(actions, dtype=np.float32)
            except (TypeError, ValueError) as e:
                raise ExperimentError("actions", f"actions: not castable to float32 ({e})") from None
        if a.shape != self._action_shape:
            raise ExperimentError("actions", f"actions: expected shape {self._action_shape}, got {a.shape}")
        if not a.flags.c_contiguous:
            a = np.ascontiguousarray(a)
        if self._mode is AutoresetMode.DISABLED and self._ended.any():
            i = int(np.flatnonzero(self._ended)[0])
            raise ExperimentError("actions", f"actions: env {i} ended its episode and autoreset_mode is "
                                             f"DISABLED; reset it first (reset(options={{'reset_mask': mask}}))")
        self._fresh(step=True)
        self._core.step(a, self._obs, self._rewards, self._terminations, self._truncations)
        self._fill_infos()
        dones = self._terminations | self._truncations
        extra = {}
        if dones.any():
            if self._stats is not None:
                extra.update(self._stats.ended(dones, self._info_arrays))
            # a world's episode ends when each of its agents has ended, now or before
            over = dones if self._active is None else np.repeat(
                (dones | ~self._active).reshape(self.num_worlds, self.num_agents).all(axis=1), self.num_agents)
            if self._mode is AutoresetMode.SAME_STEP and over.any():
                extra.update(self._reset_ended(dones, over))
            elif self._mode is AutoresetMode.DISABLED:
                self._ended |= over
        return self._out(0), self._out(1), self._out(2), self._out(3), self._infos_out(extra)

    def _reset_ended(self, dones, over):
        """SAME_STEP: the last observation and infos of the rows that ended,
        then the reset of the worlds whose episode ended (each continues
        its own random stream)."""
        ended = np.flatnonzero(dones)
        final_obs = np.zeros_like(self._obs)
        final_obs[ended] = self._obs[ended]
        final_info = {}
        for key, array in self._info_arrays.items():
            final_info[key] = np.where(dones, array, np.zeros_like(array))
            final_info["_" + key] = dones.copy()
        worlds = list(dict.fromkeys(int(r) // self.num_agents for r in np.flatnonzero(over)))
        for w in worlds:
            self._core.reset_env(w, None, self._obs)
        self._fill_infos()
        if self._stats is not None:
            self._stats.started(self._rows(worlds))
        return {"final_obs": final_obs, "_final_obs": dones.copy(), "final_info": final_info,
                "_final_info": dones.copy()}

    def _fill_infos(self):
        self._core.fill_infos(*self._info_arrays.values(), self._active)

    def _rows(self, worlds):
        """The rows of the given worlds (environments)."""
        a = self.num_agents
        return [w * a + k for w in worlds for k in range(a)]

    def _worlds_of(self, rows, field):
        """The worlds whose rows these are: every agent of a world together."""
        a = self.num_agents
        if a == 1:
            return rows
        worlds = list(dict.fromkeys(r // a for r in rows))
        if sorted(rows) != sorted(self._rows(worlds)):
            raise ExperimentError(field, f"{field}: the {a} rows of an environment (its agents) are reset "
                                         f"together; choose all of rows w*{a} .. w*{a}+{a - 1}")
        return worlds

    def _fresh(self, keep_obs=False, step=False):
        """copy=True: new arrays for the C++ side to write and the call to
        return (the observations carried over when only some rows change;
        rewards and flags only a step writes). copy=False: the same ones."""
        if not self._copy:
            return
        # np.empty with the shape and dtype at hand: a third of empty_like's cost (0.15 against 0.6 us);
        # __init__'s info arrays spelt out again, as in _infos_out (loops over a key table cost 0.5-1 us a step)
        n, obs = self.num_envs, self._obs
        self._obs = obs.copy() if keep_obs else np.empty(obs.shape, np.float32)
        if step:
            self._rewards = np.empty(n, np.float64)
            self._terminations = np.empty(n, np.bool_)
            self._truncations = np.empty(n, np.bool_)
        self._info_arrays = {"episode_index": np.empty(n, np.int64), "episode_steps": np.empty(n, np.int64),
                             "episode_return": np.empty(n, np.float64), "diverged": np.empty(n, np.bool_)}

    def _out(self, i):
        """obs, rewards, terminations, truncations (i = 0..3) as returned:
        the fresh array itself (copy=True) or a read-only view."""
        if self._copy:
            return (self._obs, self._rewards, self._terminations, self._truncations)[i]
        return self._views[i]

    def _infos_out(self, extra=None):
        """A new dict each call: the per-env counters (the fresh arrays, with
        fresh masks, or read-only views), then what this step adds (episode
        statistics, final_obs)."""
        if self._copy:
            everyone = self._everyone
            a = self._info_arrays
            infos = {"episode_index": a["episode_index"], "_episode_index": everyone.copy(),
                     "episode_steps": a["episode_steps"], "_episode_steps": everyone.copy(),
                     "episode_return": a["episode_return"], "_episode_return": everyone.copy(),
                     "diverged": a["diverged"], "_diverged": everyone.copy()}
        else:
            infos = dict(self._infos)
        if self._active is not None:
            infos["active"] = self._active.copy()
            infos["_active"] = np.ones(self.num_envs, np.bool_)
        if self._drawn is not None:
            self._core.drawn(self._drawn)
            infos["drawn"] = self._drawn.copy()
            infos["_drawn"] = np.ones(self.num_worlds, np.bool_)
        if extra:
            infos.update(extra)
        return infos

    def set_randomization(self, ranges, envs=None):
        """A curriculum: the ranges the next resets of envs draw from.
        ranges: the task's ``randomize`` object (dict), every key optional:
        "x", "y" (m), "yaw_deg", "speed" as [lo, hi], "parameters" as
        [{"path": ..., "range": [lo, hi]}] for parameters the task already
        randomises (a curriculum changes ranges, it adds none; each end must
        validate). envs: None (every env), an index, a list of indices or a
        bool mask. Refused values raise ExperimentError naming the field
        ("randomize/x", "randomize/parameters/0/range") and change nothing."""
        if not isinstance(ranges, Mapping):
            raise ExperimentError("randomize", f"randomize: must be a dict such as {{'x': [-2, 2]}}, got "
                                               f"{type(ranges).__name__}")
        try:
            text = json.dumps(ranges, allow_nan=False)
        except (TypeError, ValueError) as e:
            raise ExperimentError("randomize", f"randomize: not representable as JSON ({e})") from None
        chosen = self._chosen_envs(envs)
        if chosen is None:
            self._core.set_randomization(-1, text)
            return
        # whether new ranges validate does not depend on an env's current ones
        # (kept keys were valid), so a refusal comes at the first env, before
        # any has changed
        for i in chosen:
            self._core.set_randomization(i, text)

    def render(self, envs=None):
        """uint8 frames (k, height, width, 3) of the chosen environments
        (None: every one; an index, a list or a bool mask), each from behind
        its first agent's car, with render_mode="rgb_array"."""
        if self.render_mode != "rgb_array":
            raise ExperimentError("render_mode", "render: this env was made with render_mode=None; make it with "
                                                 "render_mode='rgb_array'")
        worlds = range(self.num_worlds) if envs is None else self._chosen_envs(envs)
        return render_frames(self._core, worlds, self._render_size)

    def drawn(self):
        """What each env's last reset drew, float64 (num_envs,
        len(layout.drawn)): x, y (m), yaw (rad), speed (m/s), then each
        parameter, for a privileged critic."""
        out = np.zeros((self.num_worlds, len(self.layout.drawn)), np.float64)
        self._core.drawn(out)
        return out

    def _chosen_envs(self, envs):
        if envs is None:
            return None
        if isinstance(envs, np.ndarray) and envs.dtype == np.bool_:
            if envs.shape != (self.num_worlds,):
                raise ExperimentError("envs", f"envs: a bool mask needs shape ({self.num_worlds},), got {envs.shape}")
            return [int(i) for i in np.flatnonzero(envs)]
        chosen = [envs] if np.ndim(envs) == 0 else list(envs)
        return list(dict.fromkeys(self._world_index(i, "envs") for i in chosen))

    def _world_index(self, env, field):
        i = _index(env, field)
        if not 0 <= i < self.num_worlds:
            raise ExperimentError(field, f"{field}: must be in [0, {self.num_worlds}), got {i}")
        return i

    def snapshot(self, env):
        """The full state of env (bytes; with several agents, env is an
        environment, not a row), restorable bit for bit, also into another
        process running the same scenario."""
        return self._core.snapshot(self._world_index(env, "env"))

    def restore(self, env, data):
        """Restores env from snapshot(); returns its new observation (its
        agents' rows with several)."""
        i = self._world_index(env, "env")
        if not isinstance(data, (bytes, bytearray, memoryview)):
            raise ExperimentError("snapshot", f"snapshot: must be bytes, got {type(data).__name__}")
        self._fresh(keep_obs=True)
        self._core.restore(i, bytes(data), self._obs)
        self._fill_infos()
        rows = self._rows([i])
        self._ended[rows] = False
        if self._stats is not None:
            self._stats.started(rows)
        obs = self._out(0)
        return obs[i] if self.num_agents == 1 else obs[rows[0]:rows[-1] + 1]

    def close(self, **kwargs):
        if self.closed:
            return
        self.close_extras(**kwargs)
        self.closed = True

    def close_extras(self, **kwargs):
        self._core.close()

    def __del__(self):
        if not getattr(self, "closed", True):
            self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __repr__(self):
        return (f"groundsim.VecEnv({self._name!r}, num_envs={self.num_envs}, "
                f"autoreset_mode={self._mode.name}, copy={self._copy})")

    def _env_index(self, env, field):
        i = _index(env, field)
        if not 0 <= i < self.num_envs:
            raise ExperimentError(field, f"{field}: must be in [0, {self.num_envs}), got {i}")
        return i

    def _envs_to_reset(self, options):
        if options is None:
            return None
        if not isinstance(options, Mapping):
            raise ExperimentError("options", f"options: must be a dict or None, got {type(options).__name__}")
        unknown = sorted(set(options) - {"env", "reset_mask", "randomize"})
        if unknown:
            raise ExperimentError("options", f"options: unknown key(s) {unknown}; supported: 'env' (an index "
                                             f"or a list of indices), 'reset_mask' (bool array of shape "
                                             f"({self.num_envs},)), 'randomize' (new ranges, the task's "
                                             f"randomize schema)")
        if "env" in options and "reset_mask" in options:
            raise ExperimentError("options", "options: give 'env' or 'reset_mask', not both")
        if "env" not in options and "reset_mask" not in options:
            return None
        if "env" in options:
            chosen = options["env"]
            chosen = [chosen] if np.ndim(chosen) == 0 else list(chosen)
            return list(dict.fromkeys(self._env_index(i, "options['env']") for i in chosen))
        mask = options["reset_mask"]
        if not (isinstance(mask, np.ndarray) and mask.dtype == np.bool_ and mask.shape == (self.num_envs,)):
            raise ExperimentError("options", f"options['reset_mask']: expected a bool array of shape "
                                             f"({self.num_envs},), got {type(mask).__name__} "
                                             f"{getattr(mask, 'dtype', '')} {np.shape(mask)}")
        return [int(i) for i in np.flatnonzero(mask)]

    def _seeds(self, seed):
        """None, an int s with s + num_worlds - 1 < 2^63, or a list of
        num_worlds ints or Nones (one per environment: with several agents,
        its rows share it)."""
        if seed is None:
            return None
        if np.ndim(seed) == 0:
            s = _index(seed, "seed")
            if not 0 <= s <= _SEED_END - self.num_worlds:
                raise ExperimentError("seed", f"seed: must be in [0, 2^63 - num_envs] (env i is seeded with "
                                              f"seed + i), got {s}")
            return s
        seeds = list(seed)
        if len(seeds) != self.num_worlds:
            raise ExperimentError("seed", f"seed: a sequence of seeds needs one per env ({self.num_worlds}), "
                                          f"got {len(seeds)}")
        for i, s in enumerate(seeds):
            if s is not None:
                seeds[i] = _index(s, f"seed[{i}]")
                if not 0 <= seeds[i] < _SEED_END:
                    raise ExperimentError(f"seed[{i}]", f"seed[{i}]: must be in [0, 2^63), got {seeds[i]}")
        return seeds
