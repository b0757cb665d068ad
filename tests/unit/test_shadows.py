"""The shared shadow module's numpy twin and settings (spec/003 §2.8): cascade splits, the
stable fit, biases, filters, point encoding, dither patterns."""

from __future__ import annotations

import numpy as np
import pytest

from app.errors import ParamError
from app.params import ParamSet
from app.render.shadows import ShadowSettings, shadow_params
from app.sim import shadows as sh
from app.sim.camera import Camera


def test_splits_blend_log_and_uniform():
    uni = sh.cascade_splits(1.0, 101.0, 4, 0.0)
    assert np.allclose(uni, [26, 51, 76, 101])
    log = sh.cascade_splits(1.0, 10000.0, 4, 1.0)
    assert np.allclose(log, [10, 100, 1000, 10000])
    half = sh.cascade_splits(1.0, 10000.0, 4, 0.5)
    assert np.allclose(half, 0.5 * log + 0.5 * sh.cascade_splits(1.0, 10000.0, 4, 0.0))
    assert sh.cascade_splits(0.2, 150.0, 0, 0.5)[-1] == pytest.approx(150.0)


def test_fig72_splits_are_doubling_not_practical():
    """Unity's 6.7/13.3/26.7/53.3 % (Fig. 72) doubles each cascade; the practical scheme at
    λ = 0.5 over Unity's near 0.2 and distance 150 does not reproduce it."""
    frac = sh.split_fractions(0.2, 150.0, 4, 0.5)
    assert frac.sum() == pytest.approx(1.0)
    assert np.abs(frac - [0.067, 0.133, 0.267, 0.533]).max() > 0.05
    # pure log splits double exactly when far / near = 16
    assert np.allclose(sh.split_fractions(1.0, 16.0, 4, 1.0) * 15, [1, 2, 4, 8])


def test_bad_split_input():
    with pytest.raises(ValueError, match="cascade count"):
        sh.cascade_splits(0.1, 10, 5)
    with pytest.raises(ValueError, match="lambda"):
        sh.cascade_splits(0.1, 10, 4, 1.5)


def test_bounding_sphere_holds_the_slice_and_ignores_rotation():
    cam = Camera(position=(1.0, 2.0, 3.0), yaw=20, pitch=-10, fov=60, near=0.1, far=50)
    c, r = sh.bounding_sphere(cam.view_matrix(), cam.fov, 1.5, 2.0, 9.0)
    corners = sh.frustum_corners(cam.view_matrix(), cam.fov, 1.5, 2.0, 9.0)
    assert np.linalg.norm(corners - c, axis=1).max() <= r + 1e-9
    cam.set(yaw=77, pitch=30)
    assert sh.bounding_sphere(cam.view_matrix(), cam.fov, 1.5, 2.0, 9.0)[1] == r


def test_stable_fit_moves_by_whole_texels():
    light = np.array([0.3, 1.0, 0.2])
    m0 = sh.ortho_fit(light, (0.0, 0.0, 0.0), 4.0, 256)
    m1 = sh.ortho_fit(light, (0.013, 0.0, 0.004), 4.0, 256)
    # a world point's map position changes by whole texels (here none: a sub-texel move)
    p = np.array([[0.5, 0.0, 0.25]])
    d = (sh.project(m1, p) - sh.project(m0, p))[0, :2] * 256
    assert np.allclose(d, np.round(d), atol=1e-6)
    loose = sh.ortho_fit(light, (0.013, 0.0, 0.004), 4.0, 256, stable=False)
    d2 = (sh.project(loose, p) - sh.project(m0, p))[0, :2] * 256
    assert not np.allclose(d2, np.round(d2), atol=1e-3)


def test_light_basis_overhead_and_horizon_finite():
    for light in ([0, 1, 0], [0, -1, 0], [1, 0, 0], [0, 1e-9, 1]):
        b = sh.light_basis(light)
        assert np.all(np.isfinite(b)) and np.allclose(b @ b.T, np.identity(3), atol=1e-9)


def test_normal_bias_is_zero_facing_the_light_and_full_at_grazing():
    n = np.array([0.0, 1.0, 0.0])
    assert np.allclose(sh.normal_bias_offset(n, n, 0.3, 0.01), 0.0)
    g = sh.normal_bias_offset(n, np.array([1.0, 0.0, 0.0]), 0.3, 0.01)
    assert g == pytest.approx(-n * 0.3 * sh.NORMAL_BIAS_TEXELS * 0.01)
    assert np.all(np.isfinite(sh.normal_bias_offset(n, n * (1 + 1e-12), 1.0, 1.0)))
    lb = sh.linear_bias_offset(np.array([0, 1.0, 0]), 0.6, 0.01)
    assert lb[1] == pytest.approx(-0.6 * sh.LINEAR_BIAS_TEXELS * 0.01)


def test_hard_two_levels_four_tap_more():
    n = 32
    depths = np.ones((n, n))
    depths[:, : n // 2] = 0.2  # an occluder on the left half
    u = np.linspace(0.3, 0.7, 400)
    uv = np.stack([u, np.full_like(u, 0.5)], -1)
    assert set(np.unique(sh.hard(depths, uv, 0.5))) == {0.0, 1.0}
    assert len(np.unique(sh.four_tap(depths, uv, 0.5))) >= 3


def test_pcss_penumbra_and_blockers():
    assert sh.pcss_penumbra(0.8, 0.4, 0.1) == pytest.approx(0.1)
    assert sh.pcss_penumbra(0.4, 0.8, 0.1) == 0.0
    depths = np.ones((16, 16))
    depths[8, 8] = 0.3
    assert sh.blocker_search(depths, (0.53, 0.53), 0.5, 2) == pytest.approx(0.3)
    assert sh.blocker_search(depths, (0.1, 0.1), 0.5, 2) == -1.0


def test_chebyshev():
    assert sh.chebyshev(0.5, 0.25, 0.4) == 1.0
    p = sh.chebyshev(0.5, 0.26, 0.7, bleed=0.0)
    assert p == pytest.approx(0.01 / (0.01 + 0.04))
    assert sh.chebyshev(0.5, 0.26, 0.7, bleed=0.3) < p
    assert np.isfinite(sh.chebyshev(0.5, 0.25, 0.7))


def test_point_encoding():
    assert sh.point_encode(0.0, 0.0, 10.0) == 0.0
    assert sh.point_encode(10.0, 0.0, 10.0) == 1.0
    with pytest.raises(ValueError, match="range"):
        sh.point_encode(1.0, 0.0, 0.0)


def test_dither_patterns():
    pats = sh.dither_patterns()
    assert pats.shape == (17, 4, 4)
    assert [int(p.sum()) for p in pats] == list(range(17))
    assert np.all(pats[1:] >= pats[:-1])  # each contains the previous one
    # every 2 × 2 block of the half pattern has two dots (ordered dither spreads them)
    half = pats[8]
    assert all(half[y:y + 2, x:x + 2].sum() == 2 for y in (0, 2) for x in (0, 2))
    y, x = np.mgrid[0:64, 0:64]
    for a in (0.25, 0.5, 0.75):
        assert sh.dither_keep(a, x, y).mean() == pytest.approx(a, abs=1 / 16)
    assert sh.dither_index(np.nan) == 0 and sh.dither_index(2.0) == 16


def test_settings_and_params():
    params = ParamSet(shadow_params("surfaces"))
    s = ShadowSettings.from_params(params, "surfaces")
    assert (s.normal_bias, s.linear_bias, s.cascades, s.split_lambda) == (0.3, 0.01, 4, 0.5)
    assert all(p.section == "spec/003 §2.8" for p in shadow_params("x"))
    for name, value in (("cascades", "3"), ("filter", "blur"), ("taps", "some"),
                        ("map_size", 8)):  # refused by the Params, before any ShadowSettings
        with pytest.raises(ParamError, match=f"shadow_{name}.*allowed"):
            params.set(f"surfaces.shadow_{name}", value)
    assert hash(s) == hash(ShadowSettings.from_params(params, "surfaces"))


def test_taps_auto_follows_the_renderer_and_the_maps_ignore_the_receivers():
    """``shadow_taps``: auto is the fast set on a software renderer, the full (reference) set on
    a GPU; full and fast are pinned either way; the maps' key ignores what only the receivers
    read (filter, taps, PCSS size, VSM blur and bleed, strength) but not a map's own setting."""
    from dataclasses import replace

    from app.gpu.programs import ProgramSpec
    from app.render.shadow_maps import receiver_defines, receiver_variants

    params = ParamSet(shadow_params("surfaces"))
    s = ShadowSettings.from_params(params, "surfaces")
    assert s.taps == "auto"
    assert (s.resolved_taps(True), s.resolved_taps(False)) == ("fast", "full")
    for pinned in ("full", "fast"):
        t = replace(s, taps=pinned)
        assert t.resolved_taps(True) == t.resolved_taps(False) == pinned
    receivers = replace(s, filter="pcss", taps="fast", pcss_light_size=0.1, vsm_blur=3,
                        vsm_bleed=0.5, strength=0.4)
    assert receivers.map_key() == s.map_key()
    for changed in (replace(s, map_size=512), replace(s, normal_bias=0.1),
                    replace(s, dithered=not s.dithered), replace(s, cascades=2)):
        assert changed.map_key() != s.map_key()
    assert receiver_defines(replace(s, filter="pcss"), True) == (("SHADOW_FILTER", 3),
                                                                 ("SHADOW_TAPS", 1))
    assert receiver_defines(None, False) == (("SHADOW_FILTER", 1), ("SHADOW_TAPS", 0))
    variants = receiver_variants(ProgramSpec("x/y", defines=(("A", 1),)))
    assert len(set(variants)) == 10 and all(v.defines[0] == ("A", 1) for v in variants)
