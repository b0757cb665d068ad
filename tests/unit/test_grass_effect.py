"""The grass effect's declarations without GL (spec/003 §2.9): the switch the village's G key
cycles, the thesis's parameters with their defaults and ranges, the slots it reads, one-line
errors for bad values, and its programs' headers and annotations."""

from __future__ import annotations

import pytest

from app.effects.grass import Grass
from app.effects.grass.methods import GS_PROGRAMS
from app.errors import ParamError
from app.gpu.shaders import ShaderLibrary
from app.params import ParamSet
from app.scenes import get_scene
from app.sim import grass as gs
from app.ui.keymap import cycle_value


@pytest.fixture(scope="module")
def params():
    return ParamSet(Grass.declare(ShaderLibrary(None)))


def test_g_cycles_the_three_methods(params):
    spec = params.spec("grass.method")
    assert spec.choices == gs.METHODS
    seen, value = [], params["grass.method"]
    for _ in range(3):
        value = cycle_value(spec, value)
        seen.append(value)
    assert sorted(seen) == sorted(gs.METHODS)
    assert get_scene("village").keymap.bindings["G"] == "cycle:grass.method"


def test_thesis_defaults_and_ranges(params):
    assert params["grass.gs_height"] == pytest.approx(0.487)  # Fig. 93's 4.87 units
    spec = params.spec("grass.gs_sections")
    assert (spec.lo, spec.hi, params["grass.gs_sections"]) == (1, 4, 3)  # Fig. 93b
    assert params["grass.cutoff"] == pytest.approx(0.2)  # the repository's _Cutoff
    assert params["grass.wind_intensity"] == pytest.approx(0.5)  # the repository's default
    assert params["grass.wind_direction"] == 90.0  # Fig. 93's (1, 0, 0)
    assert params["grass.billboard_y"] == "average"
    assert params.spec("grass.bb_planes").hi == 4
    for name in ("grass.wellness", "grass.variety", "grass.bb_scale", "grass.blade_color",
                 "grass.bb_bend", "grass.bb_steady", "grass.gust", "grass.translucency"):
        assert name in params


def test_bad_values_are_one_line_errors(params):
    with pytest.raises(ParamError, match=r"grass.method=.*allowed one of geometry"):
        params.set("grass.method", "hair")
    with pytest.raises(ParamError, match=r"grass.blades=.*allowed an integer"):
        params.set("grass.blades", -5)
    with pytest.raises(ParamError, match="grass.gs_sections"):
        params.set("grass.gs_sections", 5)


def test_slots_and_programs():
    assert Grass.consumes["terrain"] == "required"
    assert {"wind", "main_light", "shadows", "fog"} <= set(Grass.consumes)
    assert not Grass.produces  # it casts no shadow and fills no slot
    assert [dict(p.defines)["GS_SECTIONS"] for p in GS_PROGRAMS] == [1, 2, 3, 4]
    assert [dict(p.defines)["GS_MAX_VERTICES"] for p in GS_PROGRAMS] == [9, 27, 45, 63]
    assert get_scene("village").effects.index(Grass) > [e.name for e in get_scene(
        "village").effects].index("village")
