"""The grass swept where it could fail (spec/003 §2.9): every method at wind 0 and at the
strongest wind (a 40 m/s wind slot: w_i clamped to 1) and at a late time (t = 10⁵ s, where the
sines' arguments are large), on the village's own island, seen from straight above it and from
grass level; with every Billboard Y mode, section count and input. Every image: no NaN or Inf,
no negative value, bounded, and grass drawn. Then the numpy twins over their extremes: height 0
and the maximum, the camera exactly at a billboard's centre and straight above it."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from app.effects.grass import Grass
from app.frame import FrameContext
from app.gpu.device import Gpu
from app.params import ParamSet
from app.sim import grass as gs
from app.sim.camera import Camera
from app.sim.daynight import Light
from app.sim.village import Island

SIZE = (96, 64)
#: the meadow west of the plaza, at 0.3 m above its ground
MEADOW = (-28.0, 30.0)


@pytest.fixture(scope="module")
def setup(gl_ctx):
    gpu = Gpu(gl_ctx)
    effect = Grass(gpu, ParamSet(Grass.declare(gpu.shaders)), owner="grass-stability")
    target = gpu.target("grass-stability", "image", SIZE)
    island = Island()
    yield gpu, effect, target, island
    effect.release()
    gpu.free(target)
    gpu.release()


def cameras(island):
    x, z = MEADOW
    ground = island.ground(x, z)
    return {"straight down": Camera(position=(-10.0, 45.0, 10.0), yaw=0.0, pitch=-90.0, fov=70.0,
                                    near=0.1, far=400.0),
            "grass level": Camera(position=(x, ground + 0.3, z), yaw=60.0, pitch=-3.0,
                                  fov=70.0, near=0.05, far=400.0)}


def check(img: np.ndarray, empty: np.ndarray, what: str) -> None:
    assert np.isfinite(img).all(), what
    assert img.min() >= 0.0 and img.max() < 50.0, what
    assert (np.abs(img - empty)[..., :3].max(axis=-1) > 1e-4).mean() > 0.002, what


@pytest.mark.parametrize("method", gs.METHODS)
def test_every_method_from_above_and_at_grass_level_in_calm_and_gale(setup, method):
    gpu, effect, target, island = setup
    sun = Light("sun", np.array([0.3, 0.8, -0.5]), (1.0, 0.95, 0.9), 3.0, (0.2, 0.25, 0.3))
    for (name, cam), wind, t in itertools.product(cameras(island).items(),
                                                  (np.array([0.0, 0.0]), np.array([28.0, -28.0])),
                                                  (0.0, 1.0e5)):
        f = FrameContext(SIZE, cam, time=t, terrain=island, wind=wind, main_light=sun)
        effect.params.reset()
        effect.params.set("grass.blades", 0)
        target.clear()
        effect.update(f, 0.0)
        effect.draw(f, target)
        empty = target.read()
        effect.params.set("grass.method", method)
        effect.params.set("grass.blades", 12_000)
        effect.draw(f, target)
        check(target.read(), empty, f"{method} {name} wind {wind} t {t}")
    effect.params.reset()


@pytest.mark.parametrize("mode", gs.BILLBOARD_Y)
def test_billboard_modes_straight_down(setup, mode):
    gpu, effect, target, island = setup
    cam = cameras(island)["straight down"]
    f = FrameContext(SIZE, cam, time=3.0, terrain=island, wind=np.array([40.0, 0.0]))
    effect.params.reset()
    effect.params.set("grass.blades", 0)
    target.clear()
    effect.draw(f, target)
    empty = target.read()
    effect.params.set("grass.blades", 12_000)
    effect.params.set("grass.billboard_y", mode)
    effect.params.set("grass.bb_planes", 4)
    effect.draw(f, target)
    check(target.read(), empty, mode)
    effect.params.reset()


@pytest.mark.parametrize("sections,source", itertools.product((1, 4), ("scattered", "grid")))
def test_geometry_inputs_and_sections_in_a_gale(setup, sections, source):
    gpu, effect, target, island = setup
    cam = cameras(island)["grass level"]
    f = FrameContext(SIZE, cam, time=7.0, terrain=island, wind=np.array([0.0, 40.0]))
    effect.params.reset()
    effect.params.set("grass.blades", 0)
    target.clear()
    effect.draw(f, target)
    empty = target.read()
    for k, v in {"method": "geometry", "blades": 12_000, "gs_sections": sections,
                 "gs_input": source, "gs_height": 1.0, "gs_repository_height": True}.items():
        effect.params.set(f"grass.{k}", v)
    effect.draw(f, target)
    check(target.read(), empty, f"{sections} {source}")
    effect.params.reset()


def test_twins_at_their_extremes():
    tri = np.array([[1e3, 0.0, -1e3], [1e3 + 0.1, 0.0, -1e3], [1e3, 0.0, -1e3 + 0.1]])
    for s, h, wi, t in itertools.product((1, 2, 3, 4), (0.0, 1.0), (0.0, 1.0), (0.0, 1e5)):
        tris, normals = gs.gs_blade(tri, h, s, (0.0, 0.0, 0.0), wi, t, shrink=bool(s % 2))
        assert np.isfinite(tris).all() and np.isfinite(normals).all()
        assert np.allclose(np.linalg.norm(normals, axis=1), 1.0)
    up, right = np.array([0.0, 0.0, -1.0]), np.array([1.0, 0.0, 0.0])
    for mode, pos in itertools.product(gs.BILLBOARD_Y, ((0.0, 50.0, 0.0), (0.0, 0.0, 0.0))):
        f = gs.billboard_frame((0.0, 0.0, 0.0), pos, up, right, mode, 90.0)
        assert np.isfinite(f.right).all() and np.isfinite(f.normal).all()
    off = gs.bb_wind_offset(1.0, (0.0, 0.0, 0.0), 1.0, 1.0, 1e9, 1e5, 1.25, 1.0, 5.0)
    assert np.isfinite(off).all()
