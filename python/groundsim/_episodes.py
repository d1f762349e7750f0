"""What the vector env adds to Gymnasium's infos when episodes end: the
episode statistics of gymnasium.wrappers.vector.RecordEpisodeStatistics
(``episode`` = {"r", "l", "t"} and the ``_episode`` mask), and the parsing of
an autoreset mode."""

import time

import numpy as np

from ._errors import ExperimentError
from ._gym import AutoresetMode

_MODE_NAMES = {"next_step": AutoresetMode.NEXT_STEP, "same_step": AutoresetMode.SAME_STEP,
               "disabled": AutoresetMode.DISABLED}


def autoreset_mode_of(mode):
    """An AutoresetMode from itself (gymnasium's or groundsim's stand-in), its
    value ("NextStep") or its snake_case name ("next_step")."""
    if isinstance(mode, AutoresetMode):
        return mode
    value = getattr(mode, "value", mode)  # another AutoresetMode enum (gymnasium's, when ours is the stand-in)
    if isinstance(value, str):
        for candidate in AutoresetMode:
            if value == candidate.value:
                return candidate
        key = value.strip().lower().replace("-", "_")
        if key in _MODE_NAMES:
            return _MODE_NAMES[key]
    raise ExperimentError("autoreset_mode", f"autoreset_mode: must be one of {sorted(_MODE_NAMES)} (or an "
                                            f"AutoresetMode), got {mode!r}")


class EpisodeStatistics:
    """Return and length come from the C++ counters (exact, also for an env
    restored from a snapshot); ``t`` is the wall time since the episode's
    start in s, rounded to 1 us, as Gymnasium's wrapper reports it."""

    def __init__(self, num_envs):
        self._start = np.full(num_envs, time.perf_counter())

    def started(self, envs):
        self._start[envs] = time.perf_counter()

    def ended(self, dones, counters):
        now = time.perf_counter()
        stats = {"r": np.where(dones, counters["episode_return"], 0.0),
                 "l": np.where(dones, counters["episode_steps"], 0),
                 "t": np.where(dones, np.round(now - self._start, 6), 0.0)}
        # NEXT_STEP: the next episode starts with the next step
        self._start[dones] = now
        return {"episode": stats, "_episode": dones.copy()}
