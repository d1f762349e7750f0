"""Frames and videos without a display: rgb_array frames come from the C++
renderer (server/render: a chase camera behind the car, the browser page's
ground and colours, the same bytes for the same state); record_video pipes
them to Debian's ffmpeg as an H.264 MP4."""

import shutil
import subprocess

import numpy as np

from ._errors import ExperimentError

RENDER_MODES = ("rgb_array",)
DEFAULT_SIZE = (128, 96)  # width, height


def render_options(render_mode, render_size):
    """(mode, (width, height)) checked: mode None or "rgb_array", sizes in [16, 4096]."""
    if render_mode not in (None,) + RENDER_MODES:
        raise ExperimentError("render_mode", f"render_mode: must be None or 'rgb_array', got {render_mode!r}")
    try:
        width, height = (int(v) for v in render_size)
    except (TypeError, ValueError):
        raise ExperimentError("render_size", f"render_size: must be (width, height), got {render_size!r}") from None
    if not (16 <= width <= 4096 and 16 <= height <= 4096):
        raise ExperimentError("render_size", f"render_size: width and height must be in [16, 4096] px, got "
                                             f"{width} x {height}")
    return render_mode, (width, height)


def render_frames(core, worlds, size):
    """uint8 (len(worlds), height, width, 3) frames of the given environments."""
    width, height = size
    out = np.zeros((len(worlds), height, width, 3), np.uint8)
    for k, w in enumerate(worlds):
        core.render(int(w), out[k])
    return out


def record_video(env, policy, path, *, steps=None, seed=None, fps=None, crf=23):
    """Runs policy(observation) -> action on env (a groundsim.Env made with
    render_mode="rgb_array") from reset(seed) until the episode ends (or
    `steps` actions) and writes the frames to path as an H.264 MP4 with
    ffmpeg (Debian's; playable by browsers and common players). Returns
    (frames written, episode return). crf: x264's quality (lower is better
    and larger; 23 is its default)."""
    if getattr(env, "render_mode", None) != "rgb_array":
        raise ExperimentError("render_mode", "record_video: the env must be made with render_mode='rgb_array'")
    ffmpeg = shutil.which("ffmpeg")
    if ffmpeg is None:
        raise ExperimentError("ffmpeg", "record_video: ffmpeg is not installed (apt-get install ffmpeg)")
    obs, _ = env.reset(seed=seed)
    frame = env.render()
    height, width = frame.shape[:2]
    rate = fps or env.metadata.get("render_fps") or 25
    cmd = [ffmpeg, "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{width}x{height}",
           "-r", f"{rate:g}", "-i", "-", "-an", "-c:v", "libx264", "-crf", str(int(crf)), "-pix_fmt", "yuv420p",
           "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-movflags", "+faststart", str(path)]
    proc = subprocess.Popen(cmd, stdin=subprocess.PIPE)
    frames, total = 0, 0.0
    try:
        proc.stdin.write(frame.tobytes())
        frames += 1
        while steps is None or frames <= steps:
            obs, reward, terminated, truncated, _ = env.step(policy(obs))
            total += reward
            proc.stdin.write(env.render().tobytes())
            frames += 1
            if terminated or truncated:
                break
    finally:
        proc.stdin.close()
        code = proc.wait()
    if code != 0:
        raise ExperimentError("ffmpeg", f"record_video: ffmpeg exited with {code} writing {path}")
    return frames, total
