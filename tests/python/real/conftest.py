"""Fixtures of the real-library tests: the shipped tasks by id, and the
source tree's tasks (the helpers of tests/python/conftest.py)."""

import os
import pathlib
import sys

# tests/python/conftest.py's helpers (make_goal, actions, GOAL, TASKS)
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
os.environ.setdefault("GROUNDSIM_SOURCE_DIR", str(pathlib.Path(__file__).resolve().parents[3]))
from conftest import GOAL, TASKS, actions, goal_doc, make_goal  # noqa: E402,F401
