"""The tasks shipped with the package, under ids, and where their files are:
the task files (configs/tasks/*.json, and the heightfield goal.json reads)
travel in the package, under groundsim/data/. Imports nothing of the
package's environments (make.py, registration.py import this)."""

import os
import pathlib

from ._errors import ExperimentError

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


# several agents: PettingZoo's API (make_parallel), not Gymnasium's registry
_MULTI_AGENT = {"groundsim/Race-v0", "groundsim/GridRace-v0"}


