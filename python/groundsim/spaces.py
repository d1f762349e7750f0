"""Stand-ins for Gymnasium's Box and AutoresetMode, used when gymnasium is not
importable (it is not a Debian package). They hold what RL code reads from a
space: low, high, shape, dtype, sample(), contains(), seed()."""

import enum

import numpy as np


class AutoresetMode(enum.Enum):
    """Gymnasium's gymnasium.vector.AutoresetMode, same values."""

    NEXT_STEP = "NextStep"
    SAME_STEP = "SameStep"
    DISABLED = "Disabled"


class Box:
    """A box in R^shape: low <= x <= high componentwise (bounds may be inf)."""

    def __init__(self, low, high, shape=None, dtype=np.float32, seed=None):
        self.dtype = np.dtype(dtype)
        if shape is None:
            shape = np.shape(low) if np.ndim(low) else np.shape(high)
        self.shape = tuple(int(n) for n in shape)
        self.low = np.broadcast_to(np.asarray(low, dtype=self.dtype), self.shape).copy()
        self.high = np.broadcast_to(np.asarray(high, dtype=self.dtype), self.shape).copy()
        self._rng = np.random.default_rng(seed)

    def seed(self, seed=None):
        self._rng = np.random.default_rng(seed)
        return [seed]

    def sample(self):
        """Uniform where bounded on both sides, as Gymnasium's Box does:
        exponential where bounded on one side, normal where unbounded."""
        low_ok, high_ok = np.isfinite(self.low), np.isfinite(self.high)
        x = np.empty(self.shape, dtype=np.float64)
        both, none = low_ok & high_ok, ~low_ok & ~high_ok
        only_low, only_high = low_ok & ~high_ok, ~low_ok & high_ok
        x[both] = self._rng.uniform(self.low[both], self.high[both])
        x[none] = self._rng.normal(size=int(none.sum()))
        x[only_low] = self.low[only_low] + self._rng.exponential(size=int(only_low.sum()))
        x[only_high] = self.high[only_high] - self._rng.exponential(size=int(only_high.sum()))
        return x.astype(self.dtype)

    def contains(self, x):
        x = np.asarray(x)
        return bool(x.shape == self.shape and np.all(x >= self.low) and np.all(x <= self.high))

    __contains__ = contains

    def __eq__(self, other):
        return (isinstance(other, Box) and self.shape == other.shape and self.dtype == other.dtype
                and np.array_equal(self.low, other.low) and np.array_equal(self.high, other.high))

    def __repr__(self):
        return f"Box({self.low.min()}, {self.high.max()}, {self.shape}, {self.dtype})"


def batch_space(space, n):
    """n copies of a Box stacked along a new first axis."""
    return Box(np.broadcast_to(space.low, (n,) + space.shape), np.broadcast_to(space.high, (n,) + space.shape),
               dtype=space.dtype)
