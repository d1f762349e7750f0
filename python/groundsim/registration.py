"""The tasks shipped with the package under ids, and their registration
with Gymnasium: register_envs() makes gymnasium.make("groundsim/Goal-v0")
and gymnasium.make_vec("groundsim/Goal-v0", num_envs=64) work (the latter
through the vector entry point, one C++ batch, not SyncVectorEnv).

The task files (configs/tasks/*.json, and the heightfield goal.json reads)
travel in the package, under groundsim/data/."""

import os
import pathlib

from ._errors import ExperimentError
from ._gym import HAVE_GYMNASIUM

DATA_DIR = pathlib.Path(__file__).resolve().parent / "data"

# id -> task file under data/tasks
TASKS = {
    "groundsim/Goal-v0": "goal.json",
    "groundsim/Speed-v0": "speed.json",
    "groundsim/FastCar-v0": "fast_car.json",
    "groundsim/Race-v0": "race.json",  # two agents: make_parallel, or make_vec's rows
    "groundsim/GridRace-v0": "grid_race.json",  # eight agents on a grid, 2.5 m abreast
}
_SHORT = {path.rsplit(".", 1)[0]: env_id for env_id, path in TASKS.items()}


def task_ids():
    """The ids of the shipped tasks."""
    return list(TASKS)


def task_path(task):
    """The file of a shipped task, given its id ("groundsim/Goal-v0") or
    short name ("goal"); None for anything else."""
    if not isinstance(task, str) or os.path.exists(task):
        return None  # a file of that name wins over a short name
    env_id = _SHORT.get(task, task)
    if env_id not in TASKS:
        if task.startswith("groundsim/"):
            raise ExperimentError("task", f"task: unknown id {task!r}; shipped: {task_ids()}")
        return None
    return DATA_DIR / "tasks" / TASKS[env_id]


def task_source(task, files_dir=None):
    """(scenario, files_dir) for make_vec: a shipped task by id or short
    name becomes its file; anything else (path, JSON text, dict) passes."""
    path = task_path(task)
    if path is None:
        return task, files_dir
    if not path.is_file():
        raise ExperimentError("task", f"task: {task!r} is not installed with this package ({path} missing)")
    return os.fspath(path), files_dir


def make_vec_entry(num_envs=1, task="groundsim/Goal-v0", **kwargs):
    """Gymnasium's vector entry point: make_vec(task, num_envs, **kwargs).
    Gymnasium passes max_episode_steps when the spec has one; the task's
    own time_limit governs truncation, so it must be None."""
    from .make import make_vec

    if kwargs.pop("max_episode_steps", None) is not None:
        raise ExperimentError("max_episode_steps", "max_episode_steps: set the task's time_limit instead")
    scenario, files_dir = task_source(task, kwargs.pop("files_dir", None))
    return make_vec(scenario, num_envs, files_dir=files_dir, **kwargs)


# several agents: PettingZoo's API (make_parallel), not Gymnasium's registry
_MULTI_AGENT = {"groundsim/Race-v0", "groundsim/GridRace-v0"}


def register_envs():
    """Registers every shipped single-agent task with gymnasium (when
    importable) as gymnasium.make / make_vec ids; returns those ids. Safe
    to call twice."""
    ids = [env_id for env_id in TASKS if env_id not in _MULTI_AGENT]
    if not HAVE_GYMNASIUM:
        return ids
    import gymnasium

    for env_id in ids:
        if env_id in gymnasium.registry:
            continue
        gymnasium.register(id=env_id, entry_point="groundsim.env:Env",
                           vector_entry_point="groundsim.registration:make_vec_entry",
                           kwargs={"task": env_id}, disable_env_checker=False)
    return ids
