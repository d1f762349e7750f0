"""Frames without a display: render_mode="rgb_array" gives uint8 (height,
width, 3) frames from behind the car in the page's colours; the same state
renders the same bytes; record_video writes an MP4 that ffprobe reads."""

import json
import shutil
import subprocess

import numpy as np
import pytest

import groundsim
from conftest import TASKS

SKY = np.array([0x9f, 0xc4, 0xe0])


def drive(env, steps, seed=0):
    env.reset(seed=seed)
    a = np.array([0.8, 0.0, 0.3], np.float32)
    for _ in range(steps):
        env.step(a)
    return env.render()


def test_a_frame_shows_sky_ground_and_the_car():
    default = groundsim.make("goal", render_mode="rgb_array")
    default.reset(seed=0)
    assert default.render().shape == (96, 128, 3)  # the default size
    env = groundsim.make("goal", render_mode="rgb_array", render_size=(160, 120))
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (120, 160, 3) and frame.dtype == np.uint8
    # the top rows are sky (or sky-tinted fog); the bottom rows ground (green dominates)
    assert np.abs(frame[:3].reshape(-1, 3).astype(int) - SKY).max() < 40
    bottom = frame[-10:].reshape(-1, 3).astype(int)
    assert (bottom[:, 1] > bottom[:, 2]).mean() > 0.9
    # the sedan is the first vehicle: red (0xd94f3d) in the middle of the view
    middle = frame[40:110, 50:110].reshape(-1, 3).astype(int)
    red = (middle[:, 0] > middle[:, 1] + 40) & (middle[:, 0] > middle[:, 2] + 40)
    assert red.sum() > 100


def test_the_same_state_renders_the_same_bytes_and_another_differs():
    a = groundsim.make("goal", render_mode="rgb_array")
    b = groundsim.make("goal", render_mode="rgb_array")
    fa, fb = drive(a, 25), drive(b, 25)
    assert fa.tobytes() == fb.tobytes() and fa.tobytes() == a.render().tobytes()
    assert drive(b, 26).tobytes() != fa.tobytes()


def test_vector_envs_render_the_chosen_ones():
    env = groundsim.make_vec(TASKS / "goal.json", 3, 1, render_mode="rgb_array", render_size=(64, 48))
    env.reset(seed=1)
    assert env.render().shape == (3, 48, 64, 3)
    two = env.render([0, 2])
    assert two.shape == (2, 48, 64, 3)
    assert two[1].tobytes() == env.render(np.array([False, False, True]))[0].tobytes()
    assert env.metadata["render_fps"] == pytest.approx(25.0)


def test_two_agents_render_behind_the_first():
    env = groundsim.make_parallel("race", render_mode="rgb_array", render_size=(160, 120))
    env.reset(seed=0)
    frame = env.render()
    assert frame.shape == (120, 160, 3)
    # blue's car (0x3d7dd9) is beside red, in view
    px = frame.reshape(-1, 3).astype(int)
    assert ((px[:, 2] > px[:, 0] + 60) & (px[:, 2] > px[:, 1] + 20)).sum() > 20


@pytest.mark.parametrize("kwargs, field", [
    ({"render_mode": "human"}, "render_mode"),
    ({"render_mode": "rgb_array", "render_size": (8, 8)}, "render_size"),
    ({"render_mode": "rgb_array", "render_size": "big"}, "render_size"),
])
def test_bad_render_options_are_refused(kwargs, field):
    with pytest.raises(groundsim.ExperimentError) as e:
        groundsim.make_vec(TASKS / "goal.json", 1, **kwargs)
    assert e.value.field == field


def test_rendering_needs_a_render_mode_and_a_local_env():
    env = groundsim.make_vec(TASKS / "goal.json", 1)
    with pytest.raises(groundsim.ExperimentError) as e:
        env.render()
    assert e.value.field == "render_mode"
    with pytest.raises(groundsim.ExperimentError) as e:
        groundsim.make_remote_vec(TASKS / "goal.json", 1, render_mode="rgb_array")
    assert e.value.field == "render_mode" and "make_vec" in str(e.value)


@pytest.mark.skipif(shutil.which("ffmpeg") is None, reason="ffmpeg is not installed (apt-get install ffmpeg)")
def test_record_video_writes_an_mp4_ffprobe_reads(tmp_path):
    env = groundsim.make("goal", render_mode="rgb_array")
    path = tmp_path / "drive.mp4"
    frames, ret = groundsim.record_video(env, lambda obs: np.array([0.8, 0.0, 0.2], np.float32), path, steps=30,
                                         seed=2)
    assert frames == 31 and np.isfinite(ret)
    probe = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                            "stream=codec_name,width,height,nb_read_frames", "-of", "json", str(path)],
                           capture_output=True, text=True, check=True)
    stream = json.loads(probe.stdout)["streams"][0]
    assert stream["codec_name"] == "h264" and (stream["width"], stream["height"]) == (128, 96)
    assert int(stream["nb_read_frames"]) == 31
    with pytest.raises(groundsim.ExperimentError):
        groundsim.record_video(groundsim.make("goal"), lambda obs: obs, tmp_path / "x.mp4")
