"""Views (app/scenes/views.py): every scene has 3–4, each parses, names what it teaches with
its thesis section, and sets only parameters its scene has, in range; a broken view file is
one line naming the file and what is allowed."""

from __future__ import annotations

import re

import pytest

from app.errors import ParamError, UsageError
from app.runtime import scene_params
from app.scenes import SCENES
from app.scenes import views as V


@pytest.mark.parametrize("scene", sorted(SCENES))
def test_every_scene_has_three_or_four_views_that_apply(scene):
    views = V.views_of(scene)
    assert 3 <= len(views) <= 5, [v.name for v in views]
    assert len({v.title for v in views}) == len(views)
    for view in views:
        assert re.search(r"(spec/\d{3} §[\d.]+|[A-Z][a-z]+ \d{4})", view.lesson), view.lesson
        assert len(view.title) <= 60 and "\n" not in view.lesson
        params = scene_params(scene, view=view)  # every parameter exists and is in range
        for group, table in view.tables.items():
            for key, value in table.items():
                got = params[f"{group}.{key}"]
                want = tuple(value) if isinstance(value, list) else value
                assert got == pytest.approx(want) if not isinstance(want, str) else \
                    str(got) == want, (view.name, group, key, got, want)
        if view.time is not None:
            assert params["time.hour"] == pytest.approx(view.time % 24.0)


def _write(tmp_path, text):
    folder = tmp_path / "views" / "sky"
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "v.toml").write_text(text)
    return tmp_path / "views"


@pytest.mark.parametrize("text,words", [
    ("[sky]\nsun_size = 0.1\n", "no [view] table"),
    ('[view]\ntitle = "t"\nlesson = "l"\nzoom = 2\n', "unknown key 'zoom'"),
    ('[view]\ntitle = ""\nlesson = "l"\n', "title must be a non-empty string"),
    ('[view]\ntitle = "t"\nlesson = "l"\ncamera = [1, 2]\n', "camera must be"),
    ('[view]\ntitle = "t"\nlesson = "l"\ntime = 30\n', "time must be an hour"),
    ('[view]\ntitle = "t"\nlesson = "l"\nframes = 0\n', "frames must be"),
    ('[view]\ntitle = "t"\nlesson = "l"\n[sky]\nsun_size = 9\n', "out of range"),
    ('[view\n', "not valid TOML"),
])
def test_a_broken_view_is_one_line_naming_its_file(tmp_path, monkeypatch, text, words):
    monkeypatch.setattr(V, "VIEWS", _write(tmp_path, text))
    with pytest.raises(ParamError) as err:
        for view in V.views_of("sky"):
            scene_params("sky", view=view)
    message = str(err.value)
    assert words in message and "\n" not in message, message
    assert "v.toml" in message or "sky/v" in message


def test_an_unknown_view_names_the_allowed_ones():
    with pytest.raises(UsageError) as err:
        V.get_view("sky", "dawn")
    names = [v.name for v in V.views_of("sky")]
    assert all(n in str(err.value) for n in names) and "'dawn'" in str(err.value)


def test_a_view_places_the_camera_and_sets_its_hour():
    view = V.get_view("sky", "night")
    from app.sim.camera import Camera

    camera = Camera()
    assert view.place(camera)
    assert camera.position == view.camera[:3] and camera.yaw == view.camera[3] % 360
    params = scene_params("sky", view=view, sets=["time.hour=3"])  # --set wins over the view
    assert params["time.hour"] == 3.0
