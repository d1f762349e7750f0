"""Stable-Baselines3's VecEnv contract over a groundsim vector env (a
stable_baselines3.common.vec_env.VecEnv when SB3 is importable):

    venv = groundsim.sb3.make_sb3_vec("groundsim/Goal-v0", num_envs=16)
    obs = venv.reset()                       # observations only; venv.reset_infos
    obs, rewards, dones, infos = venv.step(actions)

At an episode end the returned observation is the next episode's first
(SB3 resets in the same step), the last one is
``infos[i]["terminal_observation"]`` and ``infos[i]["TimeLimit.truncated"]``
says a time limit (not a termination) ended it; ``infos[i]["episode"]`` =
{"r", "l", "t"} as SB3's Monitor writes it. seed(s) seeds env i with s + i
at the next reset (SB3's convention), set_options(o) passes reset options."""

import numpy as np

from ._errors import ExperimentError
from ._gym import AutoresetMode
from ._tasks import task_source
from .make import make_vec

try:
    from stable_baselines3.common.vec_env import VecEnv as _SB3VecEnv

    HAVE_SB3 = True
except ImportError:
    _SB3VecEnv = object
    HAVE_SB3 = False

_INFO_KEYS = ("episode_index", "episode_steps", "episode_return", "diverged")


class SB3VecEnv(_SB3VecEnv):
    """Wraps a groundsim.VecEnv made with autoreset_mode="same_step"."""

    def __init__(self, venv):
        if venv.metadata.get("autoreset_mode") is not AutoresetMode.SAME_STEP:
            raise ExperimentError("autoreset_mode", "autoreset_mode: SB3's contract needs a vector env made "
                                                    "with autoreset_mode='same_step'")
        self.venv = venv
        if HAVE_SB3:
            super().__init__(venv.num_envs, venv.single_observation_space, venv.single_action_space)
        else:
            self.num_envs = venv.num_envs
            self.observation_space = venv.single_observation_space
            self.action_space = venv.single_action_space
            self.reset_infos = [{} for _ in range(venv.num_envs)]
            self._seeds = [None] * venv.num_envs
            self._options = [{} for _ in range(venv.num_envs)]
        self.render_mode = None
        self._actions = None

    # the VecEnv contract
    def reset(self):
        seeds = None if all(s is None for s in self._seeds) else list(self._seeds)
        options = [o for o in self._options if o]
        obs, infos = self.venv.reset(seed=seeds, options=options[0] if options else None)
        self.reset_infos = self._list_infos(infos, np.zeros(self.num_envs, np.bool_), None, None)
        self._seeds = [None] * self.num_envs
        self._options = [{} for _ in range(self.num_envs)]
        return obs

    def seed(self, seed=None):
        """Env i is seeded with seed + i at the next reset()."""
        if seed is None:
            self._seeds = [None] * self.num_envs
        else:
            self._seeds = [int(seed) + i for i in range(self.num_envs)]
        return list(self._seeds)

    def set_options(self, options=None):
        """Reset options for the next reset() (one dict for every env)."""
        if isinstance(options, (list, tuple)):
            if any(o != options[0] for o in options):
                raise ExperimentError("options", "options: one dict for every env")
            options = options[0] if options else None
        self._options = [dict(options or {}) for _ in range(self.num_envs)]

    def step_async(self, actions):
        self._actions = actions

    def step_wait(self):
        if self._actions is None:
            raise ExperimentError("actions", "step_wait: no step_async before it")
        actions, self._actions = self._actions, None
        obs, rewards, terminated, truncated, infos = self.venv.step(actions)
        dones = terminated | truncated
        return obs, rewards.astype(np.float32), dones, self._list_infos(infos, dones, terminated, truncated)

    def step(self, actions):
        self.step_async(actions)
        return self.step_wait()

    def close(self):
        self.venv.close()

    def get_attr(self, attr_name, indices=None):
        value = getattr(self.venv, attr_name)
        return [value for _ in self._indices(indices)]

    def set_attr(self, attr_name, value, indices=None):
        raise ExperimentError("attr_name", f"set_attr: the environments of one batch share {attr_name!r}; "
                                           "it cannot be set per env")

    def env_method(self, method_name, *method_args, indices=None, **method_kwargs):
        method = getattr(self.venv, method_name)
        return [method(*method_args, **method_kwargs) for _ in self._indices(indices)]

    def env_is_wrapped(self, wrapper_class, indices=None):
        return [False for _ in self._indices(indices)]

    def get_images(self):
        raise ExperimentError("render_mode", "get_images: made without a render mode; nothing to render")

    def render(self, mode=None):
        return self.get_images()

    def _indices(self, indices):
        if indices is None:
            return range(self.num_envs)
        if isinstance(indices, int):
            return [indices]
        return indices

    def _list_infos(self, infos, dones, terminated, truncated):
        out = [{key: infos[key][i].item() for key in _INFO_KEYS} for i in range(self.num_envs)]
        for i in np.flatnonzero(dones):
            info = out[i]
            info["terminal_observation"] = infos["final_obs"][i]
            info["TimeLimit.truncated"] = bool(truncated[i] and not terminated[i])
            if "episode" in infos:
                info["episode"] = {k: v[i].item() for k, v in infos["episode"].items()}
            # the ended episode's own counters, not the next one's
            for key in _INFO_KEYS:
                info[key] = infos["final_info"][key][i].item()
        return out


def make_sb3_vec(task, num_envs, num_threads=0, *, files_dir=None):
    """SB3VecEnv over make_vec(task, num_envs, ..., autoreset_mode="same_step")."""
    scenario, files = task_source(task, files_dir)
    return SB3VecEnv(make_vec(scenario, num_envs, num_threads, files_dir=files, autoreset_mode="same_step"))
