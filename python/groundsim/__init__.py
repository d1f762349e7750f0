"""groundsim: vehicles on implicit ground, as vectorised environments for
reinforcement learning. See docs/experiments-python.md.

    import groundsim
    env = groundsim.make_vec("configs/tasks/goal.json", num_envs=64)
    obs, infos = env.reset(seed=0)
    obs, rewards, terminations, truncations, infos = env.step(actions)
"""

from ._errors import ExperimentError, ScenarioError, ScenarioIssue
from ._gym import HAVE_GYMNASIUM, AutoresetMode, Box
from .vector import VecEnv, make_vec

__version__ = "0.1.0"
__all__ = ["AutoresetMode", "Box", "ExperimentError", "HAVE_GYMNASIUM", "ScenarioError", "ScenarioIssue",
           "VecEnv", "make_vec"]
