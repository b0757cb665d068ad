"""The architecture's mechanisms without GL: the scene registry, bench sweeps found by module
name, frame slots refused at build time, passes run stage by stage, former parameter names, and
the keyed cache (docs/architecture.md)."""

from __future__ import annotations

import sys
import textwrap

import pytest

import app.scenes as scenes
from app.bench import scene_sweeps
from app.effects.base import Effect, Pass
from app.effects.probe import Probe
from app.errors import NaturaError
from app.frame import FrameContext, SlotMissing, Stage
from app.gpu.cache import Keyed
from app.gpu.shaders import ShaderLibrary
from app.params import Param, ParamSet
from app.scenes.base import Scene
from app.sim.camera import Camera


def test_scenes_are_found_in_their_modules_in_a_stable_order():
    assert list(scenes.SCENES) == ["sky", "probe", "materials", "planet", "noise", "clouds",
                                   "ocean", "maritime", "shading", "surfaces", "village"]
    orders = [cls.order for cls in scenes.SCENES.values()]
    assert orders == sorted(orders)
    assert all(cls.__module__ == f"app.scenes.{name}" for name, cls in scenes.SCENES.items())


def test_a_new_scene_module_is_registered_without_editing_a_list(tmp_path, monkeypatch):
    (tmp_path / "dusk.py").write_text(textwrap.dedent('''
        from app.effects.sky import Sky
        from app.scenes.base import Scene

        class DuskScene(Scene):
            name = "dusk"
            order = 15
            effects = (Sky,)
    '''))
    monkeypatch.setattr(scenes, "__path__", [*scenes.__path__, str(tmp_path)])
    try:
        found = scenes._discover()
        assert list(found)[:3] == ["sky", "dusk", "probe"], "listed by order, then name"
        twin = (tmp_path / "dusk.py").read_text().replace("DuskScene", "Other")
        (tmp_path / "dusk2.py").write_text(twin)
        with pytest.raises(RuntimeError, match="two scenes are named 'dusk'"):
            scenes._discover()
    finally:
        for mod in ("app.scenes.dusk", "app.scenes.dusk2"):
            sys.modules.pop(mod, None)


def test_bench_sweeps_are_the_module_named_like_the_scene():
    assert scene_sweeps("ocean").__name__ == "app.bench.ocean"
    assert scene_sweeps("planet").__name__ == "app.bench.planet"
    assert scene_sweeps("sky") is None and scene_sweeps("probe") is None
    assert scene_sweeps("../etc") is None and scene_sweeps("ocean.x") is None


class _NoSky(Scene):
    name = "no-sky"
    effects = (Probe,)


def test_a_scene_missing_a_required_slot_is_refused_when_it_is_built():
    with pytest.raises(NaturaError) as err:
        _NoSky.declare_params(ShaderLibrary(None))
    message = str(err.value)
    assert "probe" in message and "environment" in message and "\n" not in message
    with pytest.raises(NaturaError):
        _NoSky(None, ParamSet())
    scenes.SCENES["probe"].check_slots()  # the probe scene has the sky that produces it


def test_a_missing_slot_read_at_frame_time_names_the_consumer():
    frame = FrameContext(size=(4, 4), camera=Camera())
    with pytest.raises(SlotMissing, match="'mirror'.*'environment'"):
        frame.require("environment", by="mirror")


def _fake(name_: str, stage: Stage):
    class Fake(Effect):
        name = name_
        stages = (stage,)

        def draw(self, frame, target) -> None:
            frame.drawn.append(self.name)

    return Fake


def test_passes_run_stage_by_stage_in_the_scene_order_within_a_stage():
    class Mixed(Scene):
        name = "mixed"
        effects = (_fake("fog", Stage.FOG), _fake("clouds", Stage.VOLUMES),
                   _fake("sky", Stage.BACKGROUND), _fake("wall", Stage.OPAQUE),
                   _fake("haze", Stage.FOG))

    scene = Mixed(None, ParamSet())
    frame = FrameContext(size=(4, 4), camera=Camera())
    frame.drawn = []

    class Target:
        size = (4, 4)

    for p in scene.passes(frame, Target()):
        p.run()
    assert frame.drawn == ["sky", "wall", "clouds", "fog", "haze"]
    assert frame.image.target.size == (4, 4)
    stages = [p.stage for p in scene.passes(frame, Target())]
    assert stages == sorted(stages)


def test_an_effect_with_neither_draw_nor_passes_says_so():
    class Empty(Effect):
        name = "empty"

    with pytest.raises(NotImplementedError, match="'empty'"):
        Empty(None, ParamSet()).passes(FrameContext(size=(1, 1), camera=Camera()), None)[0].run()
    assert isinstance(Pass("x", lambda: None).stage, Stage)


def test_a_renamed_group_keeps_its_former_name():
    params = ParamSet([Param("materials.objects", "all", kind="choice", choices=("all", "slice"))])
    params.alias("material", "materials")
    params.set_from_string("material.objects=slice")
    assert params["materials.objects"] == params["material.objects"] == "slice"
    assert "material.objects" in params and "material.nothing" not in params
    materials = scenes.SCENES["materials"].declare_params(ShaderLibrary(None))
    assert materials["material.material"] == "wood"


def test_keyed_rebuilds_only_when_the_key_changes_and_releases_the_old_value():
    released = []
    k = Keyed(lambda key: [key], release=released.append)
    a = k.get(1)
    assert k.get(1) is a and k.builds == 1
    b = k.get(2)
    assert b == [2] and released == [[1]] and k.builds == 2
    k.clear()
    assert not k.built and k.value is None and released == [[1], [2]]
    assert k.get(2) is not b and k.builds == 3
