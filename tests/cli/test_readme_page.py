"""The README as a teacher reads it (issue 38): short, every link and picture there, every scene
named with its pictures and theory page, and what it says about keys, the first five minutes
and its examples true of the code. The examples themselves run in tests/cli/test_readme.py.
Nothing here opens a window or a GL context."""

from __future__ import annotations

import math
import re
import shlex
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app import DEFAULT_SHADER_ROOT, PROJECT_ROOT
from tests.helpers import readme as R

README = R.README_PATH.read_text(encoding="utf-8")
#: the pages whose relative links must lead somewhere
PAGES = (R.README_PATH, R.COMMANDS_PATH, PROJECT_ROOT / "docs" / "testing.md")
MAX_LINES = 250
SCREENSHOTS = ("docs/gallery/window.jpg", "docs/gallery/editor.jpg")


def _scene_names() -> set[str]:
    """Every scene's name without importing every scene's effects (seconds): one module of
    app/scenes per scene, named as the scene (``app.scenes.SCENES`` looks names up so)."""
    import pkgutil

    import app.scenes as scenes

    return {m.name for m in pkgutil.iter_modules(scenes.__path__)
            if m.name not in scenes._NOT_SCENES and not m.name.startswith("_")}


def test_the_scene_names_are_the_scene_modules():
    """What _scene_names relies on, checked cheaply: each name finds its scene."""
    from app.scenes import get_scene

    for name in ("sky", "village"):
        assert get_scene(name).name == name
    assert {"sky", "maritime", "village"} <= _scene_names()


def test_the_readme_is_read_in_five_minutes():
    n = len(README.splitlines())
    assert n <= MAX_LINES, f"README.md has {n} lines: at most {MAX_LINES} (move detail to docs/)"


def _slug(heading: str) -> str:
    """GitHub's anchor of a Markdown heading."""
    text = re.sub(r"[^\w\- ]", "", heading.strip().lower())
    return text.replace(" ", "-")


def _anchors(path: Path) -> set[str]:
    text = path.read_text(encoding="utf-8")
    text_no_code = re.sub(r"^```.*?^```$", "", text, flags=re.S | re.M)
    heads = {_slug(h) for h in re.findall(r"^#{1,6} (.+)$", text_no_code, flags=re.M)}
    return heads | set(re.findall(r'<a id="([^"]+)"></a>', text))


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_every_relative_link_leads_to_a_file_and_anchor_that_exist(page):
    text = re.sub(r"^```.*?^```$", "", page.read_text(encoding="utf-8"), flags=re.S | re.M)
    bad = []
    for target in re.findall(r"\]\(([^)\s]+)\)", text):
        if re.match(r"[a-z]+:", target):  # https:, mailto:
            continue
        path, _, anchor = target.partition("#")
        where = (page.parent / path).resolve() if path else page
        if not where.exists():
            bad.append(f"{target}: no such file")
        elif anchor and where.suffix == ".md" and anchor not in _anchors(where):
            bad.append(f"{target}: no anchor {anchor!r}")
    assert not bad, f"{page.name}: " + "; ".join(bad)


def test_the_readme_links_the_reference_pages():
    for target in ("docs/commands.md", "docs/testing.md", "docs/architecture.md", "docs/theory/",
                   "docs/exercises.md", "docs/gallery/README.md"):
        assert f"]({target}" in README, f"the README does not link {target}"


def test_the_screenshots_are_there_small_and_shown():
    for name in SCREENSHOTS:
        assert f"]({name})" in README, f"the README does not show {name}"
        with Image.open(PROJECT_ROOT / name) as im:
            assert im.format == "JPEG" and im.width <= 960, (name, im.format, im.size)
        assert (PROJECT_ROOT / name).stat().st_size < 300_000, name


def test_every_scene_has_a_row_with_its_pictures_and_its_theory_page():
    SCENES = _scene_names()
    rows = {m.group(1): m.group(0) for m in re.finditer(r"^\| `(\w+)` \|.*$", README, re.M)}
    assert set(rows) == set(SCENES), sorted(set(rows) ^ set(SCENES))
    theory = {p.name for p in (PROJECT_ROOT / "docs" / "theory").glob("*.md")}
    for scene, row in rows.items():
        assert f"(docs/gallery/{scene}.jpg)" in row, scene
        pages = re.findall(r"\(docs/theory/([^)#]+)", row)
        assert pages and set(pages) <= theory, (scene, pages)
    words = {11: "eleven"}
    assert f"## The {words.get(len(SCENES), len(SCENES))} scenes" in README


def test_the_frame_rate_table_lists_every_scene_and_says_the_gpu_is_not_measured():
    SCENES = _scene_names()
    section = R.sections()["Frames per second"]
    named = re.findall(r"^\| (\w+) \| [\d.]+ \([\d.]+\) \| [\d.]+ \|$", section, re.M)
    assert sorted(named) == sorted(SCENES)
    assert "On a GPU these have not been measured yet" in section


def test_the_keys_the_readme_names_are_bound():
    """The controls table and the maritime line, against the key maps."""
    from app.scenes.keymaps import FLY
    from app.scenes.maritime import MARITIME
    from app.ui.window import WINDOW_KEYS

    fly = FLY.bindings
    for key, action in {"W": "forward", "A": "left", "S": "back", "D": "right", "Q": "down",
                        "E": "up", "LEFT_SHIFT": "fast", "M": "toggle_mouse",
                        "SPACE": "toggle_time", "LEFT_BRACKET": "time_back",
                        "RIGHT_BRACKET": "time_forward", "R": "reset_camera",
                        "P": "screenshot", "F12": "screenshot", "F1": "toggle_panel",
                        "ESCAPE": "quit"}.items():
        assert fly[key] == action, key
    assert WINDOW_KEYS == {"F2": "toggle_editor", "F3": "toggle_compare"}
    sea = MARITIME.bindings
    assert sea["LEFT"].startswith("hold:boat.helm") and sea["UP"].startswith("hold:boat.throttle")
    assert sea["Z"].startswith("hold:boat.sails") and sea["X"].startswith("hold:boat.sails")
    assert sea["C"] == "cycle:maritime.camera" and sea["T"] == "toggle_time"
    assert sea["SPACE"] == "toggle_ui" and sea["ESCAPE"] == "pause_menu"
    assert [sea[f"NUMBER_{i}"] for i in range(1, 5)] == [
        f"set:maritime.weather={w}" for w in ("calm", "fair", "overcast", "storm")]


def test_the_first_five_minutes_match_the_code():
    """The walk-through's line of cloth.frag, the copy the first save offers, and what F3 starts
    with in maritime."""
    from app.teach import editor
    from app.teach.methods import axis_of
    from app.ui.compare_view import SIZES

    section = R.sections()["Your first five minutes"]
    line35 = (DEFAULT_SHADER_ROOT / "boat" / "cloth.frag").read_text().splitlines()[34]
    assert line35.strip().startswith("vec3 colour =") and line35.endswith("? uColorA : uColorB;")
    assert "line 35 (`vec3 colour = … ? uColorA : uColorB;`)" in section
    assert editor.DEFAULT_COPY == "my-glsl" and "`my-glsl`" in section
    axis = axis_of("maritime")
    assert axis is not None
    a, b = f"{axis.param}={axis.choices[1][0]}", f"{axis.param}={axis.choices[-1][0]}"
    assert f"`{a}`" in section and f"`{b}`" in section
    assert SIZES[0] == (160, 90) and SIZES[1] == (320, 180)
    assert "at 160x90 (320x180 on a GPU)" in section


def _example(word: str) -> list[str]:
    (line,) = [c for c in R.command_lines() if word in c]
    return shlex.split(line)


def _option(words: list[str], name: str) -> str:
    return words[words.index(name) + 1]


def test_the_big_sun_example_has_the_sun_in_its_frame():
    """`--set sky.sun_size=…` shows the enlarged sun: at the example's hour the sun is above the
    horizon and inside the example's camera frustum, away from its edges."""
    from app.runtime import scene_params
    from app.sim.camera import parse_camera
    from app.sim.daynight import sun_direction

    words = _example("sky.sun_size=")
    hour = float(_option(words, "--time"))
    w, h = (int(v) for v in _option(words, "--size").split("x"))
    camera = parse_camera(_option(words, "--camera"))
    sun = np.asarray(sun_direction(hour, scene_params("sky")["sky.ecliptic"]), dtype=float)
    assert sun[1] > 0.05, "the sun is below the horizon"
    right, up, forward = camera.basis()
    depth = float(np.dot(sun, forward))
    assert depth > 0, "the sun is behind the camera"
    half = math.tan(math.radians(camera.fov) / 2)
    x, y = np.dot(sun, right) / depth / (half * w / h), np.dot(sun, up) / depth / half
    assert abs(x) < 0.8 and abs(y) < 0.8, f"the sun is at ({x:.2f}, {y:.2f}) of the frame"


def test_the_frames_example_spans_a_whole_day():
    words = _example("--frames")
    frames, fps = int(_option(words, "--frames")), float(_option(words, "--fps"))
    sets = dict(s.split("=", 1) for s in (words[i + 1] for i, w in enumerate(words)
                                          if w == "--set"))
    assert sets["time.playing"] == "true"
    span = float(sets["time.speed"]) * frames / fps
    assert span == pytest.approx(24.0), f"{frames} frames at {fps} fps span {span} h"
