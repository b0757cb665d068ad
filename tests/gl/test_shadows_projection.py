"""Criterion 22 (spec/003 §6, §2.8): a directional light's hard shadow of a cube hovering over a
plane is a dark region whose centroid matches the analytic projection of the cube along the
light to within 2 px and whose area is within 10 % of it; its shadowed/lit visibility ratio is
the attenuation shadow.glsl documents, mix(1, v, strength) → 1 − strength inside the shadow.

The floor is sampled on a 256 × 256 grid over a 4 m × 4 m square: one sample is one "px"."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from app.gpu.device import Gpu
from app.render.shadow_maps import MeshCasters, ShadowProbe, ShadowSet
from app.render.shadows import ShadowSettings
from app.sim import surfaces_scene as ss
from app.sim.camera import Camera

ELEVATION, AZIMUTH = np.radians(60.0), np.radians(35.0)
LIGHT = np.array([np.cos(ELEVATION) * np.sin(AZIMUTH), np.sin(ELEVATION),
                  np.cos(ELEVATION) * np.cos(AZIMUTH)])  # toward the light
CUBE = ss.Box("cube", (0.0, 1.0, 0.0), (0.3, 0.3, 0.3))
FLOOR = ss.Box("floor", (0.0, -0.05, 0.0), (4.0, 0.05, 4.0))
SCENE = ss.SurfacesScene(boxes=[FLOOR, CUBE])
SETTINGS = ShadowSettings(map_size=512, cascades=0, filter="hard", normal_bias=0.3,
                          linear_bias=0.01, fixed_radius=3.0, fixed_centre=(0.0, 0.5, 0.0))
N, HALF = 256, 2.0
PX = 2 * HALF / N  # metres per grid sample


def grid():
    """Sample centres over the floor square: (N, N, 3), row = z index, column = x index."""
    xs = -HALF + (np.arange(N) + 0.5) * PX
    x, z = np.meshgrid(xs, xs)
    return np.stack([x, np.zeros_like(x), z], -1)


def to_px(xz):
    """World (x, z) → grid (column, row) coordinates in px."""
    return (np.asarray(xz) + HALF) / PX - 0.5


def hull(points):
    """Convex hull (counter-clockwise) of 2-D points, Andrew's monotone chain."""
    pts = sorted(map(tuple, np.round(points, 12)))

    def half(seq):
        out: list = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out[:-1]

    return np.array(half(pts) + half(pts[::-1]))


def projection():
    """The cube's corners projected along the light onto y = 0: (area m², centroid (x, z))."""
    c, h = np.array(CUBE.centre), np.array(CUBE.half)
    corners = c + h * np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)])
    flat = corners - corners[:, 1:2] / LIGHT[1] * LIGHT
    poly = hull(flat[:, [0, 2]])
    x, y = poly[:, 0], poly[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2
    centroid = np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6 * area)
    return abs(area), centroid


def centroid_px(mask):
    rows, cols = np.nonzero(mask)
    return np.array([cols.mean(), rows.mean()])


@pytest.fixture(scope="module")
def rig(gl_ctx):
    gpu = Gpu(gl_ctx)
    cas = MeshCasters(gpu, "shadow-proj", [(ss.mesh(o), 0, 1.0, 0.5, None) for o in SCENE.boxes])
    yield cas, ShadowSet(gpu, "shadow-proj"), ShadowProbe(gpu, "shadow-proj")
    gpu.release()


def visibility(rig, settings):
    cas, shadows, probe = rig
    cam = Camera(position=(0, 3, 6), yaw=0, pitch=-25, fov=60, near=0.1, far=100)
    shadows.sun.render(cas, cam, 1.0, LIGHT, settings)
    p = grid()
    v, _ = probe.visibility(shadows, p, np.tile([0.0, 1.0, 0.0], p.shape[:-1] + (1,)))
    return v


def test_analytic_references_agree():
    """The two analytic references (exact ray casting on the grid, the corners' projection)
    agree with each other (the grid's own aliasing is ~0.3 px), so either is a sound target."""
    p = grid().reshape(-1, 3) + [0, 1e-3, 0]
    exact = ss.occluded(SCENE, p, np.tile(LIGHT, (len(p), 1))).reshape(N, N)
    area, centre = projection()
    assert np.abs(centroid_px(exact) - to_px(centre)).max() < 0.5
    assert exact.sum() * PX**2 == pytest.approx(area, rel=0.02)


def test_shadow_centroid_and_area_match_the_projection(rig):
    v = visibility(rig, SETTINGS)
    dark = v < 0.5
    area, centre = projection()
    err = np.abs(centroid_px(dark) - to_px(centre))
    assert err.max() <= 2.0, f"centroid off by {err} px"
    assert dark.sum() * PX**2 == pytest.approx(area, rel=0.10)
    # the shadow is where the cube is, not elsewhere: nearly all dark samples lie in the hull
    p = grid().reshape(-1, 3) + [0, 1e-3, 0]
    exact = ss.occluded(SCENE, p, np.tile(LIGHT, (len(p), 1))).reshape(N, N)
    assert (dark != exact).sum() < 0.05 * exact.sum()


@pytest.mark.parametrize("strength", [0.6, 0.25, 1.0])
def test_lit_to_shadow_ratio_is_the_attenuation(rig, strength):
    """shadow.glsl: ShadowSun = mix(1, v, strength), so with the hard filter (v ∈ {0, 1}) the
    shadowed samples read 1 − strength and the lit ones 1."""
    full = visibility(rig, SETTINGS) < 0.5
    v = visibility(rig, replace(SETTINGS, strength=strength))
    shadowed, lit = v[full], v[~full]
    assert lit.size and shadowed.size
    assert np.ptp(shadowed) <= 2 / 255 and np.ptp(lit) <= 2 / 255  # two flat levels
    ratio = shadowed.mean() / lit.mean()
    assert ratio == pytest.approx(1.0 - strength, abs=2 / 255)
