"""groundsim: vehicles on implicit ground, as vectorised environments for
reinforcement learning. See docs/experiments.md.

    import groundsim
    env = groundsim.make_vec("configs/tasks/goal.json", num_envs=64)
    obs, infos = env.reset(seed=0)
    obs, rewards, terminations, truncations, infos = env.step(actions)

    # one env (Gymnasium's Env API), a shipped task by id
    env = groundsim.make("groundsim/Goal-v0")
    groundsim.register_envs()   # gymnasium.make / make_vec("groundsim/Goal-v0") when gymnasium is there

    # the same environments in a groundsim-server, over LCM
    env = groundsim.make_remote_vec("configs/tasks/speed.json", 64, lcm_url="udpm://239.255.76.67:7667?ttl=0")
"""

from ._errors import ExperimentError, RemoteError, ScenarioError, ScenarioIssue
from ._gym import HAVE_GYMNASIUM, AutoresetMode, Box
from .env import Env, make
from .parallel import ParallelEnv, make_parallel
from ._tasks import task_ids
from .registration import register_envs
from .make import make_remote_vec, make_vec
from .vector import VecEnv
from .video import record_video

__version__ = "0.1.0"
__all__ = ["AutoresetMode", "Box", "Env", "ExperimentError", "HAVE_GYMNASIUM", "ParallelEnv", "RemoteError",
           "ScenarioError", "ScenarioIssue", "VecEnv", "make", "make_parallel", "make_remote_vec", "make_vec",
           "record_video", "register_envs", "task_ids"]
