"""Methods 1–3 at a reduced march scale (``planet.march_scale``, planet/composite.frag's
MARCH_PASS): one ray per 2 × 2 pixels (or 4 × 4), depth-aware upsampling, and their own ray for
the pixels the interpolation cannot stand for — against the thesis's full-resolution march
(every pixel its own ray: the reference it approximates), measured where the interpolation
matters: the light shafts, the mountains' and the city's silhouettes, the horizon and the limb
seen from space. Harness: tests/helpers/planet.py."""

from __future__ import annotations

import numpy as np
import pytest

from app.effects.planet.effect import MARCH_SCALES, Planet
from tests.helpers.planet import DARK_SPACE, camera, dilate, luminance, sun_sets

SIZE = (192, 108)
GROUND = camera(pitch=4.0)                                   # the scene's default view
SHAFTS = camera(yaw=0.0, pitch=4.0)                          # toward a sun behind the mountains
SPACE = camera(pos=(0.0, 300000.0, 60.0), pitch=-30.0)       # the limb


def pair(planet, cam, sets, scale="half", size=SIZE):
    """(full, reduced) shots of one view, and the reduced pass's own-ray mask."""
    full = planet.shoot(cam, size, {**sets, "planet.march_scale": "full"}, fresh=True)
    assert planet.effect.marched_alone() is None
    reduced = planet.shoot(cam, size, {**sets, "planet.march_scale": scale}, fresh=True)
    return full, reduced, planet.effect.marched_alone()


def eight_bit(a, b) -> np.ndarray:
    """|Δ| of the 8-bit display (tone-mapped with each shot's own exposure), per pixel."""
    return np.abs(a.display - b.display).max(axis=-1) * 255.0


def test_default_is_the_reduced_march_with_the_thesis_one_switch_away(planet):
    """auto: a quarter of the resolution per side on a software renderer, half on a GPU (the
    context's Caps); full, the thesis's march, is one switch away."""
    params = {p.name: p for p in Planet.python_params()}
    assert params["planet.march_scale"].default == "auto"
    assert set(params["planet.march_scale"].choices) == {"auto", *MARCH_SCALES}
    assert {"full", "half", "quarter"} <= set(MARCH_SCALES)
    planet.shoot(GROUND, (64, 36), {"planet.method": "lut"}, fresh=True)
    want = MARCH_SCALES["quarter" if planet.gpu.caps.software else "half"]
    assert planet.effect.last_march_scale == want
    paths = Planet.context_paths(planet.gpu.caps, planet.params)
    assert "auto" in paths["planet march scale (methods 1–3)"]


@pytest.mark.parametrize("method, scale", [("shadowed", "half"), ("shadowed", "quarter"),
                                           ("lut", "half"), ("brute_force", "half")])
def test_reduced_scale_matches_the_full_march_on_shafts_and_silhouettes(planet, method, scale):
    """A low sun behind the mountains (light shafts toward the camera), Phong surfaces: in the
    shafts (the sky rays whose in-scattering the shadow map changes by ≥ 2 %), on the
    silhouettes (2 pixels either side of a mesh's edge) and over the whole image the 8-bit
    difference to the full-resolution march stays ≤ 0.25/255 on average and ≤ 3/255 at the
    99th percentile; a single pixel may reach 8/255 (its ray slips through a gap in a shadow,
    or into one, between grid rays that do not). The silhouettes march their own rays (and,
    at this small size, much of the sky by the sun, where the in-scattering changes by more
    than planet.march_contrast across a grid cell)."""
    sets = {**sun_sets(10.0, 0.0), **DARK_SPACE, "planet.surface": "phong",
            "planet.method": method}
    size = SIZE if scale == "half" else (384, 216)   # the same grid rays per side
    full, half, alone = pair(planet, SHAFTS, sets, scale, size)
    d = eight_bit(full, half)
    edges = dilate(full.mesh, 2) & dilate(~full.mesh, 2)
    assert edges.sum() > 200
    regions = {"silhouettes": edges, "image": np.ones_like(edges)}
    if method == "shadowed":
        plain = planet.shoot(SHAFTS, size, {**sets, "planet.method": "lut",
                                            "planet.march_scale": "full"})
        shafts = (np.abs(luminance(full.rgb) - luminance(plain.rgb))
                  >= 0.02 * luminance(plain.rgb)) & ~full.mesh
        assert shafts.sum() > 150, shafts.sum()
        regions["shafts"] = shafts
    for name, region in regions.items():
        err = d[region]
        assert err.mean() <= 0.25 and np.percentile(err, 99) <= 3.0 and err.max() <= 8.0, (
            name, err.mean(), np.percentile(err, 99), err.max())
    assert 0.0 < alone.mean() < 0.95, alone.mean()
    assert alone[edges].mean() > 0.5           # the silhouettes march their own rays
    assert np.any(d > 0.0)                     # the interpolated pixels are not the full march


def test_grid_pixels_are_the_full_march_and_the_limb_holds(planet):
    """Seen from space (the limb's thin glow, the ground through the whole atmosphere): within
    3/255 everywhere; every pixel of the grid (even x and y) is its own full-resolution march
    to float rounding, since the grid marches exactly those rays."""
    full, half, alone = pair(planet, SPACE, {})
    d = eight_bit(full, half)
    assert d.max() <= 3.0 and d.mean() <= 0.1, (d.max(), d.mean())
    grid = full.rgb[::-1][::2, ::2]           # rows from the bottom, as the GPU counts them
    got = half.rgb[::-1][::2, ::2]
    assert np.abs(got - grid).max() <= 1e-4 * max(float(np.abs(grid).max()), 1e-6)
    assert 0.0 < alone.mean() < 0.25, alone.mean()


def test_default_view_marches_few_rays_and_debug_views_compose_as_the_image(planet):
    """The default view at 320×180: at half the resolution per side few pixels march their own
    ray (the meshes' edges, the horizon: about 15 %; 7 % at 640×360); at a quarter the same
    bounds hold as at half on the smaller view, and the in-scattering (on black) and the
    transmittance (on white) views make the image: the choice of interpolated pixels depends
    on neither the surface nor the view."""
    sets = {"planet.method": "shadowed"}
    _, _, alone = pair(planet, GROUND, sets, size=(320, 180))
    assert 0.0 < alone.mean() < 0.25, alone.mean()
    full, quarter, alone = pair(planet, GROUND, sets, scale="quarter")
    d = eight_bit(full, quarter)
    assert d.mean() <= 0.25 and np.percentile(d, 99) <= 3.0 and d.max() <= 8.0, (
        d.mean(), np.percentile(d, 99), d.max())
    t = planet.shoot(GROUND, SIZE, {**sets, "planet.march_scale": "quarter",
                                    "planet.debug_view": "out_scatter"})
    i = planet.shoot(GROUND, SIZE, {**sets, "planet.march_scale": "quarter",
                                    "planet.debug_view": "in_scatter"})
    assert np.abs(quarter.rgb - (quarter.gcolour * t.rgb + i.rgb)).max() < 1e-4
