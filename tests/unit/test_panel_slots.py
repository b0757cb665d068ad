"""The panel says which effects of a scene read another's frame slots (app/ui/panel.py's
``slot_readers``): effects never name each other, so the wind's text comes from the scene."""

from __future__ import annotations

import pytest

from app.scenes import get_scene


class _Scene:
    def __init__(self, name):
        self.instances = list(get_scene(name).effects)

    def active(self, effect):
        return True


@pytest.mark.parametrize("scene, readers", [
    ("village", "wind read here by Fog, Grass"),
    ("maritime", "wind read here by Volumetric clouds, model B (maritime thesis), Ocean, "
                 "Sailing boat"),
])
def test_the_wind_readers_are_the_scenes_own(scene, readers):
    from app.ui.panel import slot_readers

    s = _Scene(scene)
    wind = next(e for e in s.instances if e.name == "wind")
    assert slot_readers(s, wind) == readers


def test_no_reader_no_line():
    from app.ui.panel import slot_readers

    s = _Scene("sky")
    assert slot_readers(s, s.instances[0]) is None


def test_the_wind_names_no_other_effect():
    import app.effects.wind as package
    import app.effects.wind.effect as module
    from app.effects.wind import Wind

    words = " ".join([package.__doc__ or "", module.__doc__ or "", Wind.__doc__ or "",
                      *(p.doc for p in Wind.python_params())]).lower()
    for other in ("ocean", "cloud", "sail", "flag", "boat", "grass", "fog"):
        assert other not in words, other
