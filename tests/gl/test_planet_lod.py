"""The mountains' level of detail (``planet.mountain_lod_px``): the coarsest mesh whose cells
span at most that many pixels at the mountains' nearest point, the shadow map drawn from the
same mesh. Against the finest mesh (``planet.mountain_lod_px = 0``, the former one): the
silhouette and the image. Harness: tests/helpers/planet.py."""

from __future__ import annotations

import numpy as np

from app.effects.planet.effect import MOUNTAIN_GRIDS, mountain_bounds, mountain_grid
from app.effects.planet.geometry import mountains
from tests.helpers.planet import R, camera

GROUND = camera(pitch=4.0)


def test_the_grid_follows_the_mountains_footprint():
    """The default view (the nearest mountain 7 km away): 96² cells at 640×360 (9 px each), the
    finest at 1280×720 and above (cells of 18 px at 96²); the finest always with 0, and with the
    camera on the mountains (no distance to project over)."""
    pos = (0.0, 2.0, 60.0)
    assert mountain_grid(pos, 60.0, 360, R, 10.0) == 96
    assert mountain_grid(pos, 60.0, 720, R, 10.0) == 192
    assert mountain_grid(pos, 60.0, 1080, R, 10.0) == 192
    assert mountain_grid(pos, 60.0, 360, R, 0.0) == 192
    lo, hi = mountain_bounds(R)
    inside = (lo + hi) / 2.0
    assert mountain_grid(inside, 60.0, 360, R, 64.0) == 192
    far = (0.0, 2.0, 60_000.0)                    # 67 km: even 1080 rows take the coarse mesh
    assert mountain_grid(far, 60.0, 1080, R, 10.0) == 96


def test_coarse_mesh_keeps_the_fine_meshs_heights():
    """Every vertex of the 96² grid is a vertex of the 192² grid, at the same position."""
    fine = mountains(R, 20000.0, MOUNTAIN_GRIDS[0])[0].reshape(193, 193, 11)[:, :, :3]
    coarse = mountains(R, 20000.0, MOUNTAIN_GRIDS[1])[0].reshape(97, 97, 11)[:, :, :3]
    assert np.allclose(coarse, fine[::2, ::2], atol=1e-2)


def test_coarse_mesh_keeps_the_silhouette_and_its_shadow_map(planet):
    """The default view at 320×180 (the coarse mesh: cells of 4.6 px): the mesh covers the
    same pixels but for ≤ 1.5 % of them (0.7 %: where a ridge moved by a pixel, the image
    changes there and only there), the 8-bit image differs by ≤ 0.25/255 on average and
    ≤ 3/255 at the 99th percentile; the shadow map is drawn again for the other mesh, and only
    then (it shows the mesh the camera sees)."""
    size = (320, 180)
    effect = planet.effect
    fine = planet.shoot(GROUND, size, {"planet.mountain_lod_px": 0.0}, fresh=True)
    assert effect.grid == 192
    passes = effect.shadow_passes
    coarse = planet.shoot(GROUND, size, {}, fresh=True)
    assert effect.grid == 96 and effect.shadow_passes == passes + 1
    planet.shoot(GROUND, size, {}, fresh=True)
    assert effect.shadow_passes == passes + 1           # once per sun direction and mesh
    flips = (fine.mesh != coarse.mesh).sum() / fine.mesh.sum()
    d = np.abs(fine.display - coarse.display).max(axis=-1) * 255.0
    assert flips <= 0.015 and d.mean() <= 0.25 and np.percentile(d, 99) <= 3.0, (
        flips, d.mean(), np.percentile(d, 99))
