"""A directional light's penumbra in world units: PCSS's width for the sun, the taps of
the light's disc, and the bench's ray-cast reference of an area light's visibility
(app/bench/surfaces_shadows.py), checked against the analytic visibility of a disc light behind
a straight edge."""

from __future__ import annotations

import numpy as np
import pytest

from app.bench import surfaces_shadows as bench
from app.sim import shadows as sh
from app.sim import surfaces_scene as ss


def test_parallel_penumbra_is_the_light_cone_at_the_blocker():
    # 2 D tan θ: a blocker 1.2 m up under a sun of tan θ = 0.05 blurs over 0.12 m
    assert sh.pcss_penumbra_parallel(1.5, 0.3, 0.05) == pytest.approx(0.12)
    assert sh.pcss_penumbra_parallel(0.3, 1.5, 0.05) == 0.0  # no blocker in front
    # metres in, metres out: the map's fit (its depth range) does not enter
    d = np.array([0.5, 1.0, 2.0])
    assert np.allclose(sh.pcss_penumbra_parallel(d, 0.0, 0.05), 0.1 * d)


def test_disc_taps_cover_the_disc_evenly():
    taps = sh.disc_taps(32)
    r2 = (taps ** 2).sum(1)
    assert r2.max() < 1.0
    assert r2.mean() == pytest.approx(0.5, abs=1e-12)  # a uniform disc's E[r²]
    assert np.abs(taps.mean(0)).max() < 0.05  # centred
    # each half of the disc, cut along any diameter, holds half the taps (± 2)
    for a in np.linspace(0, np.pi, 7):
        side = taps @ [np.cos(a), np.sin(a)] > 0
        assert abs(int(side.sum()) - 16) <= 2


def _segment_visibility(s):
    """The visible fraction of a unit disc whose part u < s is blocked."""
    s = np.clip(s, -1.0, 1.0)
    return 1.0 - (np.pi - np.arccos(s) + s * np.sqrt(1.0 - s * s)) / np.pi


def test_ray_cast_reference_matches_the_disc_behind_an_edge():
    """A slab 1 m over the floor covering x < 0, the sun overhead with angular radius 0.05: the
    visibility across the edge is the disc's segment, V(x) = 1 − A(−x / R) with R = tan θ."""
    scene = ss.SurfacesScene(boxes=[ss.Box("slab", (-5.0, 1.0, 0.0), (5.0, 0.01, 5.0))])
    xs = np.linspace(-0.08, 0.08, 41)
    p = np.stack([xs, np.zeros_like(xs), np.zeros_like(xs)], -1)[None]
    v, err = bench.area_visibility(scene, p, (0.0, 1.0, 0.0), 0.05, (64, 1024))
    radius = np.tan(0.05) * (0.99 - 1e-3)  # the slab's underside, from the points' offset
    exact = _segment_visibility(-xs / radius)
    assert np.abs(v[0] - exact).max() < 0.01
    assert err["error_mean"] < 0.005 and err["refined_points"] > 20
    assert bench.soft_fraction(v) == pytest.approx(bench.soft_fraction(exact[None]), abs=0.03)


def test_errors_split_penumbra_from_the_floor():
    truth = np.array([0.0, 0.0, 1.0, 1.0, 0.5])
    v = np.array([0.0, 0.0, 1.0, 1.0, 0.0])
    e = bench.errors(v, truth)
    assert e["mae"] == pytest.approx(0.1) and e["mae_penumbra"] == pytest.approx(0.5)


def test_inside_marks_the_floor_under_standing_solids():
    scene = ss.default_scene()
    pts = np.array([[-1.6, 0.0, -2.2], [2.7, 0.0, -2.4], [0.6, 0.0, -1.6], [3.5, 0.0, 3.5]])
    assert bench.inside(scene, pts).tolist() == [True, True, False, False]
