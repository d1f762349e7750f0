"""One environment with Gymnasium's single-env API (a gymnasium.Env when
gymnasium is importable): groundsim.make(task) -> Env with reset, step,
render, close, observation_space, action_space and np_random.

It is a vector env of one, without autoreset: after an episode ends, step()
refuses until reset() is called, as Gymnasium's OrderEnforcing and
PassiveEnvChecker expect of a single env."""

import numpy as np

from ._errors import ExperimentError
from ._gym import Env as _GymEnv
from ._gym import HAVE_GYMNASIUM
from ._tasks import task_source
from .make import make_vec

_INFO_KEYS = ("episode_index", "episode_steps", "episode_return", "diverged")


class Env(_GymEnv):
    """A task of a scenario (a path, a registered id such as
    ``"groundsim/Goal-v0"``, a JSON string or a dict), one car per env.

    info: ``episode_index``, ``episode_steps``, ``episode_return``,
    ``diverged`` (Python scalars); with ``episode_statistics=True`` also
    Gymnasium's ``episode`` = {"r", "l", "t"} in the step that ends an
    episode (off by default, so that gymnasium's RecordEpisodeStatistics
    wrapper, which refuses a duplicate, can be applied as usual)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": None}

    def __init__(self, task="groundsim/Goal-v0", *, render_mode=None, render_size=(128, 96), files_dir=None,
                 num_threads=1, episode_statistics=False):
        scenario, files = task_source(task, files_dir)
        self._vec = make_vec(scenario, 1, num_threads, files_dir=files, copy=True, autoreset_mode="disabled",
                             episode_statistics=episode_statistics, render_mode=render_mode,
                             render_size=render_size)
        if self._vec.num_agents > 1:
            agents = list(self._vec.layout.agents)
            self._vec.close()
            raise ExperimentError("task", f"task: {len(agents)} agents {agents}; one env drives one: use "
                                          f"groundsim.make_parallel (PettingZoo) or make_vec (rows)")
        self.render_mode = render_mode
        self.observation_space = self._vec.single_observation_space
        self.action_space = self._vec.single_action_space
        control_dt = self.layout.dt * self.layout.control_period
        self.metadata = dict(self.metadata, render_fps=1.0 / control_dt)
        self._shape = self.action_space.shape
        self._needs_reset = True
        if not HAVE_GYMNASIUM:
            self._np_random = None
            self.spec = None

    @property
    def layout(self):
        """Component names, dt, control period (groundsim._core.Layout)."""
        return self._vec.layout

    @property
    def unwrapped(self):
        return self

    if not HAVE_GYMNASIUM:
        @property
        def np_random(self):
            """numpy Generator seeded by reset(seed=...) (gymnasium.Env's)."""
            if self._np_random is None:
                self._np_random = np.random.default_rng()
            return self._np_random

        @np_random.setter
        def np_random(self, value):
            self._np_random = value

    def reset(self, *, seed=None, options=None):
        """A new episode: (observation, info). seed: None (the env's own
        stream goes on) or an int in [0, 2^63). options: None or
        {"randomize": ranges} (set_randomization first)."""
        if HAVE_GYMNASIUM:
            super().reset(seed=seed)
        elif seed is not None:
            self._np_random = np.random.default_rng(seed)
        if options is not None and set(options) - {"randomize"}:
            raise ExperimentError("options", f"options: a single env takes only 'randomize', got "
                                             f"{sorted(options)}")
        obs, infos = self._vec.reset(seed=seed, options=options or None)
        self._needs_reset = False
        return obs[0], self._info(infos)

    def step(self, action):
        """action: shape action_space.shape, cast to float32 (NaN refused,
        finite values clipped). Returns (observation, reward, terminated,
        truncated, info)."""
        if self._needs_reset:
            raise ExperimentError("step", "step: the episode has ended (or never started); call reset() first")
        try:
            a = np.asarray(action, dtype=np.float32)
        except (TypeError, ValueError) as e:
            raise ExperimentError("action", f"action: not castable to float32 ({e})") from None
        if a.shape != self._shape:
            raise ExperimentError("action", f"action: expected shape {self._shape}, got {a.shape}")
        try:
            obs, rew, term, trunc, infos = self._vec.step(a[None, :])
        except ExperimentError as e:
            raise ExperimentError(e.field.replace("actions[0]", "action"),
                                  str(e).replace("actions[0]", "action")) from None
        terminated, truncated = bool(term[0]), bool(trunc[0])
        self._needs_reset = terminated or truncated
        return obs[0], float(rew[0]), terminated, truncated, self._info(infos)

    def render(self):
        """With render_mode="rgb_array": the frame, uint8 (height, width, 3),
        from behind the car (the same state gives the same bytes)."""
        if self.render_mode is None:
            raise ExperimentError("render_mode", "render: this env was made with render_mode=None; nothing to "
                                                 "render")
        return self._vec.render([0])[0]

    def close(self):
        self._vec.close()

    def set_randomization(self, ranges):
        """A curriculum: the ranges the next resets draw from
        (VecEnv.set_randomization)."""
        self._vec.set_randomization(ranges)

    def drawn(self):
        """What the last reset drew, float64 (len(layout.drawn),)."""
        return self._vec.drawn()[0]

    def snapshot(self):
        """The full state (bytes), restorable bit for bit (VecEnv.snapshot)."""
        return self._vec.snapshot(0)

    def restore(self, data):
        """Restores snapshot(); returns the observation."""
        obs = self._vec.restore(0, data)
        self._needs_reset = False
        return obs

    def _info(self, infos):
        info = {key: infos[key][0].item() for key in _INFO_KEYS}
        if "episode" in infos:
            info["episode"] = {k: v[0].item() for k, v in infos["episode"].items()}
        return info

    def __repr__(self):
        return f"groundsim.Env({self._vec._name!r})"

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False


def make(task="groundsim/Goal-v0", **kwargs):
    """groundsim.Env(task, **kwargs): a registered id ("groundsim/Goal-v0"),
    a short name ("goal"), a path, a JSON string or a dict."""
    return Env(task, **kwargs)
