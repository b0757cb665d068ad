"""The sun's PCSS penumbra in world units (spec/003 §2.8): on the surfaces lab's floor,
the fraction of points in PCSS's penumbra matches the ray-cast visibility of a disc light
(app/bench/surfaces_shadows.py, independent of the shadow maps) within 10 % whatever the
orthographic map's fit radius, at one texel size; the former width, from the map's normalised
depths, moved with the fit."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from app.bench import surfaces_shadows as bench
from app.gpu.device import Gpu
from app.render.shadow_maps import ShadowProbe, ShadowSet
from app.render.shadows import ShadowSettings
from app.sim import surfaces_scene as ss

TEXEL = 10.0 / 1024  # metres: 1024 texels over the 5 m fit, as the bench
GRID = 160
BASE = ShadowSettings(cascades=0, fixed_centre=(0.0, 0.5, 0.0), distance=12.0, filter="pcss",
                      pcss_light_size=float(np.tan(bench.LIGHT_RADIUS)))


@pytest.fixture(scope="module")
def floor(gl_ctx):
    gpu = Gpu(gl_ctx)
    scene = ss.default_scene()
    cas = bench._casters(gpu, scene)
    shadows, probe = ShadowSet(gpu, "penumbra-test"), ShadowProbe(gpu, "penumbra-test")
    cam = bench._camera()
    p, n = bench._floor(GRID)
    depth = (p - np.asarray(cam.position)) @ cam.forward()
    seen = ~bench.inside(scene, p)
    truth, err = bench.area_visibility(scene, p, bench.SUN, bench.LIGHT_RADIUS, (32, 256))
    rev = [0]

    def pcss(radius: float, world: bool = True) -> np.ndarray:
        s = replace(BASE, fixed_radius=radius, map_size=int(round(2 * radius / TEXEL)))
        rev[0] += 1
        shadows.sun.pcss_world = world
        shadows.sun.render(cas, cam, 1.0, bench.SUN, s, revision=rev[0])
        v = probe.visibility(shadows, p, n, depth)[0]
        shadows.sun.pcss_world = True
        return v[seen]

    yield pcss, truth[seen], err
    shadows.release()
    gpu.release()


def test_the_reference_states_a_small_error(floor):
    _, truth, err = floor
    assert err["error_mean"] < 0.002 and err["error_max"] < 0.05
    assert 0.02 < bench.soft_fraction(truth) < 0.05  # the floor's penumbra: ~3.4 %


def test_sun_pcss_penumbra_matches_the_ray_cast_at_every_fit(floor):
    pcss, truth, _ = floor
    want = bench.soft_fraction(truth)
    got = {r: bench.soft_fraction(pcss(r)) for r in bench.FIT_RADII}
    for r, f in got.items():
        assert f == pytest.approx(want, rel=0.10), (r, got, want)
    assert max(got.values()) - min(got.values()) < 0.01 * want  # the fit does not enter


def test_the_former_width_moved_with_the_fit_and_erred_more(floor):
    """What the fix changed (pcss_world false is the former shader path): its soft fraction
    grew with the fit radius (2.55 → 3.22 % on the bench's grid) and it was further from the
    ray cast, on all points and on the penumbra."""
    pcss, truth, _ = floor
    former = [bench.soft_fraction(pcss(r, world=False)) for r in (5.0, 20.0)]
    assert former[1] > 1.1 * former[0]
    now, before = bench.errors(pcss(5.0), truth), bench.errors(pcss(5.0, world=False), truth)
    assert now["mae"] < 0.8 * before["mae"]
    assert now["mae_penumbra"] < 0.8 * before["mae_penumbra"]
