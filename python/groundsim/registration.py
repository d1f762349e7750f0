"""The shipped tasks' registration with Gymnasium: register_envs() makes
gymnasium.make("groundsim/Goal-v0") and gymnasium.make_vec("groundsim/Goal-v0",
num_envs=64) work (the latter through the vector entry point, one C++
batch, not SyncVectorEnv). The ids and files are in _tasks.py."""

from ._errors import ExperimentError
from ._gym import HAVE_GYMNASIUM
from ._tasks import _MULTI_AGENT, DATA_DIR, TASKS, task_ids, task_path, task_source  # noqa: F401
from .make import make_vec


def make_vec_entry(num_envs=1, task="groundsim/Goal-v0", **kwargs):
    """Gymnasium's vector entry point: make_vec(task, num_envs, **kwargs).
    Gymnasium passes max_episode_steps when the spec has one; the task's
    own time_limit governs truncation, so it must be None."""
    if kwargs.pop("max_episode_steps", None) is not None:
        raise ExperimentError("max_episode_steps", "max_episode_steps: set the task's time_limit instead")
    scenario, files_dir = task_source(task, kwargs.pop("files_dir", None))
    return make_vec(scenario, num_envs, files_dir=files_dir, **kwargs)


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
