"""The command line, run as a user runs it (issue 2 items 6, 9 and 10): headless renders to PNG
and EXR read back, nothing overwritten without --force, every bad argument → exit 2 with one
line naming the culprit and what is allowed, and the no-display fallback (the bench JSON:
tests/bench/test_bench.py).

Images are tiny (64×36): CI has two cores and llvmpipe.
"""

from __future__ import annotations

import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app.sim.daynight import sun_direction
from tests.helpers.cli import CONTEXT_LINE, SIZE, SMALL, messages, run, usage_error
from tests.helpers.images import read_exr


def render(tmp_path: Path, *args: str) -> subprocess.CompletedProcess:
    return run("render", "sky", "--size", SMALL, *args, cwd=tmp_path)


# ---- renders -----------------------------------------------------------------------------------

def test_render_png(tmp_path):
    r = render(tmp_path, "--time", "18.5", "--out", "sunset.png")
    assert r.returncode == 0, r.stderr
    out = tmp_path / "sunset.png"
    assert r.stdout.strip() == "sunset.png"
    with Image.open(out) as im:
        assert im.format == "PNG" and im.size == SIZE and im.mode == "RGB"
        pixels = np.asarray(im)
    assert pixels.std() > 0  # not a flat image
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sunset.png"]  # no temporary file


def sun_camera(hour: float) -> str:
    """``--camera`` looking straight at the sun (yaw 0 = north = −z, 90 = east = +x)."""
    d = sun_direction(hour, (0.0, 0.6, -1.0))  # sky.ecliptic's default
    yaw = math.degrees(math.atan2(d[0], -d[2]))
    pitch = math.degrees(math.asin(d[1]))
    return f"0,2,0,{yaw:.4f},{pitch:.4f},60"


def test_render_exr_is_linear_radiance(tmp_path):
    r = render(tmp_path, "--time", "12", "--camera", sun_camera(12.0), "--out", "noon.exr")
    assert r.returncode == 0, r.stderr
    img = read_exr(tmp_path / "noon.exr")
    assert img.shape == (SIZE[1], SIZE[0], 3) and img.dtype == np.float32
    assert np.isfinite(img).all()
    assert img.min() >= 0.0
    assert img.max() > 1.0  # not tone-mapped: the sun disk is far brighter than white
    row, col = np.unravel_index(np.argmax(img.sum(axis=-1)), img.shape[:2])
    # the sun is where we aimed
    assert abs(row - (SIZE[1] - 1) / 2) <= 2 and abs(col - (SIZE[0] - 1) / 2) <= 2

    # control: looking away from the sun (at the horizon opposite it), the bright values are gone
    yaw = float(sun_camera(12.0).split(",")[3]) + 180.0
    r = render(tmp_path, "--time", "12", "--camera", f"0,2,0,{yaw},5,60", "--out", "away.exr")
    assert r.returncode == 0, r.stderr
    away = read_exr(tmp_path / "away.exr")
    assert np.isfinite(away).all() and away.max() < 0.05 * img.max()


def test_existing_output_is_not_overwritten_without_force(tmp_path):
    out = tmp_path / "taken.png"
    out.write_bytes(b"not an image, but mine")
    line = usage_error(render(tmp_path, "--out", "taken.png"))
    assert "taken.png" in line and "--force" in line
    assert out.read_bytes() == b"not an image, but mine"

    r = render(tmp_path, "--out", "taken.png", "--force")
    assert r.returncode == 0, r.stderr
    with Image.open(out) as im:
        assert im.size == SIZE


def test_multi_frame_render_checks_every_name_first(tmp_path):
    (tmp_path / "f-0001.png").write_bytes(b"mine")
    line = usage_error(render(tmp_path, "--frames", "3", "--out", "f.png"))
    assert "f-0001.png" in line
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f-0001.png"]  # nothing written at all
    assert (tmp_path / "f-0001.png").read_bytes() == b"mine"


def test_frames_write_numbered_files_with_a_progress_bar(tmp_path):
    r = render(tmp_path, "--frames", "3", "--fps", "2", "--out", "anim.png")
    assert r.returncode == 0, r.stderr
    names = [f"anim-{i:04d}.png" for i in range(1, 4)]  # numbered from 1, like single renders
    assert r.stdout.split() == names
    for name in names:
        with Image.open(tmp_path / name) as im:
            assert im.size == SIZE
    for done in ("1/3", "2/3", "3/3"):  # a progress bar on stderr, up to the last frame
        assert done in r.stderr, r.stderr
    assert "[" + "#" * 30 + "]" in r.stderr


# ---- bad arguments: exit 2, one line -----------------------------------------------------------

def test_unknown_scene(tmp_path):
    line = usage_error(run("render", "atlantis", "--out", "x.png", cwd=tmp_path))
    assert "atlantis" in line and "sky" in line and "probe" in line
    assert not (tmp_path / "x.png").exists()


def test_unknown_parameter(tmp_path):
    line = usage_error(render(tmp_path, "--set", "sky.sun_sise=0.1", "--out", "x.png"))
    assert "sky.sun_sise" in line and "sky.sun_size" in line
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("value, why", [("abc", "not a number"), ("5", "out of range"),
                                        ("-1", "out of range"), ("nan", "not finite")])
def test_bad_parameter_value(tmp_path, value, why):
    line = usage_error(render(tmp_path, "--set", f"sky.sun_size={value}", "--out", "x.png"))
    assert "sky.sun_size" in line and why in line and "[0, 1]" in line
    assert not (tmp_path / "x.png").exists()


@pytest.mark.parametrize("args, must_contain", [
    (["--size", "64"], ["--size", "WxH"]),
    (["--size", "axb"], ["--size", "WxH"]),
    (["--size", "64x"], ["--size"]),
    (["--size", "0x36"], ["--size", "out of range"]),
    (["--size", "99999x10"], ["--size", "out of range"]),
    (["--time", "25"], ["--time", "[0, 24]"]),
    (["--camera", "1,2"], ["--camera", "X,Y,Z"]),
    (["--camera", "0,2,0,0,100"], ["pitch", "[-90, 90]"]),
    (["--frames", "0"], ["--frames", "1..100000"]),
    (["--set", "sky.sun_size"], ["name=value"]),
    (["--preset", "missing.toml"], ["missing.toml", "does not exist"]),
    (["--out", "x.jpg"], ["x.jpg", ".png, .exr"]),
    (["--out", "no/such/folder/x.png"], ["no/such/folder", "does not exist"]),
    (["--out", "."], ["."]),
    (["--bogus-flag"], ["--bogus-flag"]),
])
def test_bad_arguments(tmp_path, args, must_contain):
    line = usage_error(render(tmp_path, *args))
    assert line.startswith("natura: ")
    for part in must_contain:
        assert part in line, line
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_unwritable_output_folder(tmp_path):
    if os.geteuid() != 0:
        folder = tmp_path / "locked"
        folder.mkdir()
        folder.chmod(0o500)
    elif Path("/proc").is_dir():
        folder = Path("/proc")  # root may write anywhere on disk, but not here
    else:
        pytest.skip("running as root without /proc: no folder is unwritable")
    try:
        line = usage_error(render(tmp_path, "--out", str(folder / "x.png")))
        assert str(folder) in line and "not writable" in line
    finally:
        if folder != Path("/proc"):
            folder.chmod(0o700)


def test_missing_subcommand_argument(tmp_path):
    line = usage_error(run("render", cwd=tmp_path))
    assert "scene" in line


# ---- listings ----------------------------------------------------------------------------------

def test_scenes_lists_sky_and_probe(tmp_path):
    r = run("scenes", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    names = [line.split()[0] for line in r.stdout.splitlines() if line and not line[0].isspace()]
    assert {"sky", "probe"} <= set(names)


def test_params_lists_the_sky_parameters(tmp_path):
    r = run("params", "sky", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    line = next(line for line in r.stdout.splitlines() if line.strip().startswith("sky.sun_size"))
    assert "0.05" in line and "[0, 1]" in line
    assert "time.hour" in r.stdout
    # the window's scale is automatic by default: shown as the word a user types, not as 0
    line = next(line for line in r.stdout.splitlines() if "output.scale =" in line)
    assert line.split("=")[1].split()[0] == "'auto'", line
    line = usage_error(run("params", "atlantis", cwd=tmp_path))
    assert "atlantis" in line and "sky" in line


def test_params_of_an_annotated_copy(tmp_path):
    r = run("shaders", "copy", "mine", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    with (tmp_path / "mine" / "sky" / "sky_radiance.glsl").open("a") as f:
        f.write("uniform float uSeaGlow; // @param 0.5 [0, 3] glow of the sea\n")
    r = run("params", "sky", "--shaders", "mine", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    assert "sky.sea_glow" in r.stdout and "[0, 3]" in r.stdout
    assert "sky.sea_glow" not in run("params", "sky", cwd=tmp_path).stdout


# ---- no display --------------------------------------------------------------------------------

def test_no_display_renders_the_default_scene_headless(tmp_path):
    """``natura`` with no scene and no display renders the default scene to a new PNG, and
    never overwrites a picture an earlier run left (one is there already: the same check as
    running twice, for one render of the default scene instead of two). At a small ``--size``:
    the README walk-through (test_readme.py) runs the bare command at its default size."""
    earlier = tmp_path / "natura-maritime-0001.png"
    earlier.write_bytes(b"an earlier run's picture")
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    r = run("--size", SMALL, cwd=tmp_path, env=env)
    assert r.returncode == 0, r.stderr
    err = messages(r.stderr)
    assert len(err) == 1 and "no display" in err[0].lower(), r.stderr
    assert CONTEXT_LINE + "OpenGL" in r.stderr  # and which context rendered it instead
    out = r.stdout.strip().splitlines()
    assert len(out) == 1, r.stdout
    path = tmp_path / out[0]
    assert path.is_file() and path.suffix == ".png"
    assert path.name.startswith("natura-maritime")  # the scene the picker highlights first
    with Image.open(path) as im:
        assert im.format == "PNG" and im.size == SIZE
    assert path != earlier and earlier.read_bytes() == b"an earlier run's picture"


def test_a_dead_x_display_is_named_not_called_unset(tmp_path):
    """DISPLAY set to a server that is not running: the message says so (it used to claim
    DISPLAY was unset), and the scene is rendered headless all the same."""
    dead = next(f":{n}" for n in range(157, 200) if not Path(f"/tmp/.X11-unix/X{n}").exists())
    env = {**{k: v for k, v in os.environ.items() if k != "WAYLAND_DISPLAY"}, "DISPLAY": dead}
    r = run("window", "sky", "--size", "32x18", cwd=tmp_path, env=env)
    assert r.returncode == 0, r.stderr
    (line,) = messages(r.stderr)
    assert f"the X display '{dead}' does not answer" in line and "unset" not in line, line
    assert (tmp_path / r.stdout.strip()).is_file()


def test_time_on_a_scene_without_a_sky_is_refused(tmp_path):
    proc = run("render", "planet", "--time", "5", "--size", "32x18", "--out",
               str(tmp_path / "p.png"), cwd=tmp_path)
    assert proc.returncode == 2
    assert (len(proc.stderr.strip().splitlines()) == 1 and "--time" in proc.stderr
            and "planet" in proc.stderr)
    assert not (tmp_path / "p.png").exists()


@pytest.mark.parametrize("scene,view", [("planet", "shafts"), ("materials", "low-sun")])
def test_render_and_window_open_on_the_scenes_best_view_and_view_none_on_its_defaults(
        tmp_path, scene, view):
    """Issue 38: the planet opens on its light shafts (the sun in frame), the materials on the
    cube and ball filling the frame; ``--view none`` gives the parameters' own defaults (what
    the tests and ``natura bench`` start from)."""
    shots = {}
    for name, extra in (("plain", ()), ("view", ("--view", view)), ("none", ("--view", "none"))):
        r = run("render", scene, "--size", "64x36", *extra, "--out", f"{name}.png", cwd=tmp_path)
        assert r.returncode == 0, r.stderr
        with Image.open(tmp_path / f"{name}.png") as im:
            shots[name] = np.asarray(im.convert("RGB"), dtype=float)
    assert np.array_equal(shots["plain"], shots["view"])
    assert np.abs(shots["plain"] - shots["none"]).mean() > 5.0
