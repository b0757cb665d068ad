"""Views from the command line, as a user types them: `natura scenes` lists them, `natura render
SCENE --view NAME` is the view's camera, hour and parameters (and --set still wins), a view
name that does not exist is one line naming those that do."""

from __future__ import annotations

import numpy as np
from PIL import Image

from app.scenes import SCENES
from app.scenes.views import get_view, views_of
from tests.helpers.cli import run, usage_error


def test_natura_scenes_lists_every_view(tmp_path):
    r = run("scenes", cwd=tmp_path)
    assert r.returncode == 0, r.stderr
    for scene in SCENES:
        for view in views_of(scene):
            assert f"--view {view.name}: {view.title}" in r.stdout


def test_render_with_a_view_is_the_view_spelled_out(tmp_path):
    view = get_view("sky", "night")
    x, y, z, yaw, pitch, fov = view.camera
    a = run("render", "sky", "--view", "night", "--size", "64x36", "--out", "a.png", cwd=tmp_path)
    b = run("render", "sky", "--time", str(view.time), "--camera",
            f"{x},{y},{z},{yaw},{pitch},{fov}", "--size", "64x36", "--out", "b.png", cwd=tmp_path)
    c = run("render", "sky", "--view", "night", "--set", "time.hour=12", "--size", "64x36",
            "--out", "c.png", cwd=tmp_path)
    assert a.returncode == b.returncode == c.returncode == 0, a.stderr + b.stderr + c.stderr
    pa, pb, pc = (np.asarray(Image.open(tmp_path / n), dtype=int) for n in ("a.png", "b.png",
                                                                            "c.png"))
    assert np.array_equal(pa, pb)
    assert np.abs(pa - pc).mean() > 20  # noon instead of night: --set wins over the view


def test_an_unknown_view_is_one_line(tmp_path):
    line = usage_error(run("render", "sky", "--view", "dusk", "--size", "8x8", cwd=tmp_path))
    assert "'dusk'" in line and "noon" in line and "allowed" in line
    assert not list(tmp_path.iterdir())
