"""The ground fog plane's wisps (spec/003 §2.11 a, beyond the thesis: glsl/fog/plane.frag's
fog.plane_opacity, fog.plane_breakup, fog.plane_hug, fog.plane_grazing): at their defaults the
plane is the thesis's Custom/Fog to the bit; each knob only thins it (never adds coverage), and
does what it says — the opacity scales the alpha, the banks leave clear ground, the hug thins the
fog where the ground comes up to the plane, the grazing factor thins it seen from above."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.effects.fog import Fog
from app.effects.fog import plane as pl
from app.frame import FrameContext
from app.gpu.shaders import ShaderLibrary
from app.params import ParamSet
from app.sim.camera import Camera

OWNER = "test-fog-wisps"
SIZE = (128, 128)
T = 30.0  # sin(t/8) < 0: the cutoff is 0, the whole texture shows


class Flat:
    """A flat ground at ``h`` (1.6 m: the island's plateau)."""

    bounds = (-100.0, -100.0, 100.0, 100.0)
    sea_level = 0.0
    revision = 0

    def __init__(self, h=1.6):
        self.h = h

    def height(self, x, z):
        return np.full(np.broadcast(np.asarray(x), np.asarray(z)).shape, self.h)


def draw(gpu, *sets, camera=None, terrain=None):
    params = ParamSet(Fog.declare(ShaderLibrary(None)))
    for s in ("fog.mode=off", *sets):
        params.set_from_string(s)
    fog = Fog(gpu, params)
    target = gpu.target(OWNER, "image", SIZE)
    try:
        cam = camera or Camera(position=(12.0, 12.0, 12.0), yaw=0.0, pitch=-90.0, fov=90.0,
                               near=0.1, far=500.0)
        f = FrameContext(size=SIZE, camera=cam, time=T)
        f.terrain = terrain or Flat()
        f.wind = np.array([3.0, 0.0])
        fog.update(f, 0.0)
        target.clear((0.0, 0.0, 0.0, 1.0))
        f.image = f.image_for(target)
        for p in fog.passes(f, target):
            p.run()
        return target.read()[..., :3].max(-1)
    finally:
        fog.release()
        gpu.free(target)


def test_the_defaults_are_the_thesis_s_plane(gpu):
    base = draw(gpu)
    same = draw(gpu, "fog.plane_opacity=1", "fog.plane_breakup=0", "fog.plane_hug=0",
                "fog.plane_grazing=0")
    assert np.array_equal(base, same) and base.max() > 0.3


def test_opacity_scales_the_alpha(gpu):
    full, half = draw(gpu), draw(gpu, "fog.plane_opacity=0.5")
    seen = full > 0.05
    assert np.allclose(half[seen], 0.5 * full[seen], rtol=0.03, atol=2e-3)


def test_the_banks_leave_clear_ground_and_never_add_fog(gpu):
    full, banks = draw(gpu), draw(gpu, "fog.plane_breakup=1")
    assert np.all(banks <= full + 1e-4)
    clear_full = float(np.mean(full < 0.02))
    clear_banks = float(np.mean(banks < 0.02))
    assert clear_banks > clear_full + 0.1  # gaps open between the banks
    assert banks.max() > 0.6 * full.max()  # where a bank lies, the wisps keep their weight


def test_the_hug_thins_the_fog_where_the_ground_comes_up_to_the_plane(gpu):
    # the plane 0.35 m above the ground: a hug of 0.35 m or more thins it, less leaves it
    full = draw(gpu)
    loose = draw(gpu, "fog.plane_hug=0.1")
    tight = draw(gpu, "fog.plane_hug=1.0")
    seen = full > 0.05
    assert np.allclose(loose[seen], full[seen], atol=3e-3)
    ratio = float(np.median(tight[seen] / full[seen]))
    t = 0.35 / 1.0
    assert ratio == pytest.approx(t * t * (3.0 - 2.0 * t), abs=0.04)  # smoothstep(0, hug, 0.35)


def test_the_grazing_factor_thins_the_fog_seen_from_above(gpu):
    top, plain = draw(gpu, "fog.plane_grazing=1"), draw(gpu)
    c = slice(SIZE[0] // 2 - 8, SIZE[0] // 2 + 8)
    centre = plain[c, c] > 0.05
    assert centre.any()
    # straight down at the centre (|v·n| > 0.99 there): 1 − |v·n| < 0.01
    assert float(np.max(top[c, c][centre] / plain[c, c][centre])) < 0.02
    low = Camera(position=(0.0, 2.6, 30.0), yaw=0.0, pitch=-4.0, fov=60.0, near=0.1, far=500.0)
    graze, plain = draw(gpu, "fog.plane_grazing=1", camera=low), draw(gpu, camera=low)
    far = plain[: SIZE[1] // 2 - 4] > 0.05  # the far plane, just under the horizon
    assert far.any()
    assert float(np.median(graze[: SIZE[1] // 2 - 4][far] / plain[: SIZE[1] // 2 - 4][far])) > 0.9


def test_the_mask_carries_the_layer_s_depth():
    lay = pl.plane_layout(Flat(), 0.3)
    tex = lay.mask_texture()
    assert tex.shape == (pl.MASK_SIZE, pl.MASK_SIZE, 2)
    assert np.allclose(tex[..., 1], 0.3 / pl.DEPTH_RANGE)
    none = pl.plane_layout(None, 0.4).mask_texture()
    assert np.allclose(none[..., 1], 0.4 / pl.DEPTH_RANGE) and math.isclose(none[..., 0].min(), 1)
