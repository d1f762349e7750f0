"""Gymnasium's classes when gymnasium (1.x, which has AutoresetMode) is
importable, groundsim.spaces' stand-ins otherwise."""

try:
    from gymnasium import Env
    from gymnasium.spaces import Box
    from gymnasium.vector import AutoresetMode, VectorEnv
    from gymnasium.vector.utils import batch_space

    HAVE_GYMNASIUM = True
except ImportError:
    from .spaces import AutoresetMode, Box, batch_space

    Env = object
    VectorEnv = object
    HAVE_GYMNASIUM = False

__all__ = ["AutoresetMode", "Box", "Env", "HAVE_GYMNASIUM", "VectorEnv", "batch_space"]
