"""The factories of vector envs: make_vec (in process) and make_remote_vec
(a vectorised session of groundsim-server over LCM), from a shipped task's
id, a scenario file, JSON text or a dict."""

import json
import math
import os
from collections.abc import Mapping

from . import _core
from ._episodes import autoreset_mode_of
from ._errors import ExperimentError
from ._tasks import task_source
from .vector import VecEnv, _index
from .video import render_options


def _scenario_source(scenario):
    """(text, path, name) of a scenario given as a dict, JSON text (str or
    bytes) or a path to a file: text is None for a file, path None otherwise."""
    if isinstance(scenario, Mapping):
        try:
            text = json.dumps(scenario, allow_nan=False)
        except (TypeError, ValueError) as e:
            raise ExperimentError("scenario", f"scenario: not representable as JSON ({e})") from None
        return text, None, str(scenario.get("name", "scenario"))
    if isinstance(scenario, (bytes, bytearray)):
        return bytes(scenario).decode("utf-8", errors="replace"), None, "scenario"
    if isinstance(scenario, str) and scenario.lstrip().startswith("{"):
        return scenario, None, "scenario"
    if isinstance(scenario, (str, os.PathLike)):
        path = os.fspath(scenario)
        if not os.path.isfile(path):
            raise FileNotFoundError(f"scenario: no such file: {path!r}")
        return None, path, os.path.splitext(os.path.basename(path))[0]
    raise ExperimentError("scenario", "scenario: must be a path, a JSON string or a dict, got "
                                      f"{type(scenario).__name__}")


def _reject_duplicates(pairs):
    keys = [k for k, _ in pairs]
    if len(keys) != len(set(keys)):
        raise ValueError("duplicate key")
    return dict(pairs)


def _with_tolerance(text, path, files_dir, tolerance):
    """(text, files_dir) of the scenario with ``accuracy.tolerance`` set.
    Anything this cannot read as a JSON object (malformed, duplicate keys, an
    ``accuracy`` that is not an object) is passed on unchanged, so the
    scenario layer names the problem as it would without a tolerance."""
    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, float)) or not math.isfinite(tolerance):
        raise ExperimentError("tolerance", f"tolerance: must be a finite number (0.01 for 1%), got {tolerance!r}")
    if path is not None:
        with open(path, "rb") as f:
            text = f.read().decode("utf-8", errors="replace")
        files_dir = os.path.dirname(os.path.abspath(path))
    try:
        doc = json.loads(text, object_pairs_hook=_reject_duplicates)
    except ValueError:
        return text, files_dir
    if not isinstance(doc, dict) or not isinstance(doc.get("accuracy", {}), dict):
        return text, files_dir
    doc.setdefault("accuracy", {})["tolerance"] = float(tolerance)
    if path is not None:
        doc.setdefault("name", os.path.splitext(os.path.basename(path))[0])
    return json.dumps(doc, allow_nan=False), files_dir


_OPTIONS_DOC = """
    render_mode: None or "rgb_array" (render() returns frames);
    render_size: (width, height) of a frame, default (128, 96).
    copy: True (default) returns fresh arrays from reset() and step(); False
    returns read-only views of buffers the next call overwrites.
    autoreset_mode: "next_step" (default), "same_step" or "disabled" (or a
    gymnasium AutoresetMode); see VecEnv.
    episode_statistics: put Gymnasium's ``episode`` / ``_episode`` in the
    infos of a step where episodes end (default True).
    drawn_in_infos: put what each env's last reset drew in ``infos["drawn"]``
    (num_envs, len(layout.drawn)) every step (default False)."""


def make_vec(scenario, num_envs, num_threads=0, *, files_dir=None, copy=True, autoreset_mode="next_step",
             episode_statistics=True, drawn_in_infos=False, render_mode=None, render_size=(128, 96), tolerance=None):
    """num_envs environments of a scenario with a ``task`` section, stepped
    in this process on num_threads threads (0: one per core, 1: the calling
    thread) with the GIL released.

    scenario: a shipped task's id ("groundsim/Goal-v0", groundsim.task_ids())
    or short name ("goal"), a path to a JSON file (the heightfields it names
    are read next to it), a JSON string, or a dict. For the last two, files_dir says
    where named files are read from (none are readable without it).
    tolerance: the error you accept (0.01 for 1%; docs/accuracy.md,
    "Accuracy on demand"): one pilot on the scene chooses integrator, step and
    contact substeps for every environment, replacing the scenario's own.
    Raises ScenarioError for a bad scenario or task, ExperimentError for bad
    arguments. The result does not depend on num_threads, bit for bit."""
    options = {"copy": copy, "autoreset_mode": autoreset_mode_of(autoreset_mode),
               "episode_statistics": episode_statistics, "drawn_in_infos": drawn_in_infos,
               "render_mode": render_mode, "render_size": render_size}
    render_options(render_mode, render_size)
    n = _index(num_envs, "num_envs")
    threads = _index(num_threads, "num_threads")
    if not 1 <= n < 2**31:
        raise ExperimentError("num_envs", f"num_envs: must be at least 1, got {n}")
    if not 0 <= threads < 2**31:
        raise ExperimentError("num_threads", f"num_threads: must be >= 0 (0: one per core), got {threads}")
    scenario, files_dir = task_source(scenario, files_dir)
    text, path, name = _scenario_source(scenario)
    if tolerance is not None:
        text, files_dir = _with_tolerance(text, path, files_dir, tolerance)
        path = None
    if path is not None:
        return VecEnv(_core.make_vec_env_from_file(path, n, threads), name, **options)
    if files_dir is not None:
        files_dir = os.fspath(files_dir)
    return VecEnv(_core.make_vec_env(text, n, threads, files_dir), name, **options)


def make_remote_vec(scenario, num_envs, lcm_url=None, *, timeout=30.0, files_dir=None, shards=1, copy=True,
                    autoreset_mode="next_step", episode_statistics=True, drawn_in_infos=False, render_mode=None):
    """num_envs environments of a scenario with a ``task`` section, run in a
    vectorised session of groundsim-server over LCM (docs/protocol.md),
    with the same API and the same results, bit for bit, as make_vec.

    scenario: a path to a JSON file (the heightfields it names are read
    next to it and sent with it, as make_vec reads them), a JSON string, or
    a dict (files read relative to files_dir and sent; none without it,
    unless the server has them under its --terrain-dir). lcm_url: the server's
    (None: LCM_DEFAULT_URL or LCM's default). timeout: seconds to wait for
    a reply. Raises ScenarioError or ExperimentError as make_vec does (the
    server names the field: num_envs above its --max-envs is "num_envs"),
    RemoteError when the server is gone or parts of a reply are missing.
    shards: split the environments over this many vectorised sessions,
    stepped at once; on a fleet (docs/fleet.md) each is placed by the
    fleet, so they spread over its servers; env i is seeded seed + i
    whatever the split, so the results are make_vec's, bit for bit.
    close() stops the session(s)."""
    if render_mode is not None:
        raise ExperimentError("render_mode", "render_mode: a remote environment does not render (its state lives "
                                             "in the server); make_vec with the same seed runs the same bits and renders")
    options = {"copy": copy, "autoreset_mode": autoreset_mode_of(autoreset_mode),
               "episode_statistics": episode_statistics, "drawn_in_infos": drawn_in_infos}
    n = _index(num_envs, "num_envs")
    if not 1 <= n < 2**31:
        raise ExperimentError("num_envs", f"num_envs: must be at least 1, got {n}")
    k = _index(shards, "shards")
    if not 1 <= k <= n:
        raise ExperimentError("shards", f"shards: must be in [1, num_envs = {n}], got {k}")
    if not (isinstance(timeout, (int, float)) and timeout > 0):
        raise ExperimentError("timeout", f"timeout: must be a positive number of seconds, got {timeout!r}")
    scenario, files_dir = task_source(scenario, files_dir)
    text, path, name = _scenario_source(scenario)
    if path is not None:
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
        files_dir = os.path.dirname(os.path.abspath(path))
    elif files_dir is not None:
        files_dir = os.fspath(files_dir)
    return VecEnv(_core.make_remote_vec_env(text, n, lcm_url or "", float(timeout), files_dir, k), name, **options)


make_vec.__doc__ += _OPTIONS_DOC
make_remote_vec.__doc__ += _OPTIONS_DOC
