"""Several agents in one environment with PettingZoo's parallel API:

    env = groundsim.make_parallel("groundsim/Race-v0")
    observations, infos = env.reset(seed=0)
    while env.agents:
        actions = {agent: policy(observations[agent]) for agent in env.agents}
        observations, rewards, terminations, truncations, infos = env.step(actions)

Agents are the task's `agents` (vehicle names); an agent that terminates
leaves env.agents (its car brakes to rest and stays an obstacle) until the
episode ends for all, and the caller resets. The batched form of the same
task is make_vec(task, num_envs): rows = environments x agents, with
infos["active"] masking the rows whose agent has left."""

import warnings

import numpy as np

from ._errors import ExperimentError
from ._tasks import task_source
from .make import make_vec

try:
    from pettingzoo import ParallelEnv as _PZParallelEnv
except ImportError:
    _PZParallelEnv = object

_INFO_KEYS = ("episode_index", "episode_steps", "episode_return", "diverged")


class ParallelEnv(_PZParallelEnv):
    """PettingZoo's ParallelEnv contract: a pettingzoo.ParallelEnv when
    PettingZoo is importable (its tests, e.g. parallel_api_test, look at
    ``unwrapped``), the same API duck-typed otherwise."""

    metadata = {"name": "groundsim_parallel_v0", "render_modes": ["rgb_array"], "is_parallelizable": True}

    def __init__(self, task, *, files_dir=None, num_threads=1, render_mode=None, render_size=(128, 96)):
        scenario, files = task_source(task, files_dir)
        self._vec = make_vec(scenario, 1, num_threads, files_dir=files, copy=True, autoreset_mode="disabled",
                             episode_statistics=False, render_mode=render_mode, render_size=render_size)
        self.render_mode = render_mode
        self.possible_agents = list(self._vec.layout.agents)
        self.agents = []
        self.observation_spaces = {a: self._vec.single_observation_space for a in self.possible_agents}
        self.action_spaces = {a: self._vec.single_action_space for a in self.possible_agents}
        self._row = {a: i for i, a in enumerate(self.possible_agents)}
        self._shape = self._vec.single_action_space.shape

    @property
    def num_agents(self):
        return len(self.agents)

    @property
    def max_num_agents(self):
        return len(self.possible_agents)

    @property
    def layout(self):
        return self._vec.layout

    @property
    def unwrapped(self):
        return self

    def observation_space(self, agent):
        return self.observation_spaces[self._agent(agent, "agent")]

    def action_space(self, agent):
        return self.action_spaces[self._agent(agent, "agent")]

    def reset(self, seed=None, options=None):
        """options: None or a dict; its "randomize" (new ranges) is used,
        other keys are ignored with a warning naming them: PettingZoo's API
        test resets with options it made up ({"options": 1})."""
        if options is not None and not isinstance(options, dict):
            raise ExperimentError("options", f"options: must be a dict or None, got {type(options).__name__}")
        if options:
            unknown = sorted(set(options) - {"randomize"})
            if unknown:
                warnings.warn(f"options: ignoring unknown key(s) {unknown}; a parallel env uses 'randomize'",
                              stacklevel=2)
            options = {k: v for k, v in options.items() if k == "randomize"} or None
        obs, infos = self._vec.reset(seed=seed, options=options)
        self.agents = list(self.possible_agents)
        return ({a: obs[i] for a, i in self._row.items()},
                {a: self._info(infos, i) for a, i in self._row.items()})

    def step(self, actions):
        """actions: {agent: action} for every agent in self.agents (and no
        other). Returns dicts keyed by those agents."""
        if not self.agents:
            raise ExperimentError("step", "step: no agent is left (the episode ended); call reset()")
        if not isinstance(actions, dict):
            raise ExperimentError("actions", f"actions: must be a dict {{agent: action}}, got "
                                             f"{type(actions).__name__}")
        batch = np.zeros((len(self.possible_agents),) + self._shape, np.float32)
        for agent, action in actions.items():
            self._agent(agent, "actions")
            if agent not in self.agents:
                raise ExperimentError(f"actions[{agent!r}]", f"actions[{agent!r}]: agent {agent!r} is done "
                                                             f"(it left at the end of its episode)")
            try:
                a = np.asarray(action, dtype=np.float32)
            except (TypeError, ValueError) as e:
                raise ExperimentError(f"actions[{agent!r}]", f"actions[{agent!r}]: not castable to float32 "
                                                             f"({e})") from None
            if a.shape != self._shape:
                raise ExperimentError(f"actions[{agent!r}]", f"actions[{agent!r}]: expected shape "
                                                             f"{self._shape}, got {a.shape}")
            if not np.isfinite(a).all():
                raise ExperimentError(f"actions[{agent!r}]", f"actions[{agent!r}]: must be finite, got {a}")
            batch[self._row[agent]] = a
        missing = [a for a in self.agents if a not in actions]
        if missing:
            raise ExperimentError("actions", f"actions: missing for agent(s) {missing}")
        obs, rew, term, trunc, infos = self._vec.step(batch)
        live = self.agents
        out = ({a: obs[self._row[a]] for a in live}, {a: float(rew[self._row[a]]) for a in live},
               {a: bool(term[self._row[a]]) for a in live}, {a: bool(trunc[self._row[a]]) for a in live},
               {a: self._info(infos, self._row[a]) for a in live})
        self.agents = [a for a in live if not (term[self._row[a]] or trunc[self._row[a]])]
        return out

    def state(self):
        """Every agent's observation, concatenated in possible_agents order."""
        return self._vec._obs.reshape(-1).copy()

    def render(self):
        """With render_mode="rgb_array": the frame from behind the first agent's car."""
        if self.render_mode is None:
            raise ExperimentError("render_mode", "render: this env was made with render_mode=None; nothing to render")
        return self._vec.render([0])[0]

    def close(self):
        self._vec.close()

    def _agent(self, agent, field):
        if agent not in self._row:
            raise ExperimentError(field, f"{field}: unknown agent {agent!r}; agents: {self.possible_agents}")
        return agent

    def _info(self, infos, row):
        return {key: infos[key][row].item() for key in _INFO_KEYS}


def make_parallel(task, **kwargs):
    """groundsim.ParallelEnv(task, **kwargs): a task with `agents`, by id,
    short name, path, JSON string or dict."""
    return ParallelEnv(task, **kwargs)
