"""The toon water's numpy twins (app/sim/toon_water.py, spec/003 §2.10) and its parameters:
the Fresnel ramp within 1/255 of 0.018 + 0.982·(1 − u)^5 (criterion 20), the reflection's
staircase at step 0.15 (criterion 13: at most 8 levels), the Simple type's 3 bands, the depth
fog's weights (monotonic, and the document's and repository's formulas recovered), the
tileable normal map, and Fig. 115's defaults and the repository's ranges."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from app.effects.toon_water import ToonWater
from app.errors import NaturaError
from app.gpu.shaders import ShaderLibrary
from app.params import ParamSet
from app.sim import toon_water as tw


@pytest.fixture(scope="module")
def params() -> ParamSet:
    return ParamSet(ToonWater.glsl_params(ShaderLibrary(None)) + ToonWater.python_params())


def test_criterion_20_the_formula_and_its_ramp():
    assert tw.fresnel_water(1.0) == pytest.approx(0.0180, abs=5e-4)
    assert tw.fresnel_water(0.0) == pytest.approx(1.0)
    assert tw.fresnel_water(0.5) == pytest.approx(0.0487, abs=1e-3)
    assert tw.WATER_F0_EXACT == pytest.approx(0.0180, abs=5e-5)  # (1 − 1.31)²/(1 + 1.31)²
    ramp = tw.fresnel_ramp()
    assert ramp.dtype == np.float32 and ramp.shape == (tw.RAMP_WIDTH,)
    u = np.linspace(0.0, 1.0, 100001)
    err = np.abs(tw.fresnel_water_ramp(ramp, u) - tw.fresnel_water(u))
    assert err.max() < 0.05 / 255.0, err.max() * 255
    assert ramp[0] == 1.0 and ramp[-1] == pytest.approx(0.018)  # both ends exact
    # painted in 8 bits (the thesis's GIMP ramp): each texel within half a level
    painted = tw.fresnel_ramp(bits=8)
    assert np.abs(painted - ramp).max() <= 0.5 / 255.0 + 1e-7
    assert np.allclose(painted * 255.0, np.round(painted * 255.0), atol=1e-4)
    err8 = np.abs(tw.fresnel_water_ramp(painted, u) - tw.fresnel_water(u))
    assert err8.max() < 1.0 / 255.0
    # a ramp too coarse for the criterion fails it: the check can fail
    coarse = np.abs(tw.fresnel_water_ramp(tw.fresnel_ramp(8), u) - tw.fresnel_water(u))
    assert coarse.max() > 1.0 / 255.0


def test_the_ramp_is_sampled_at_texel_centres_at_both_ends():
    w = 64
    assert tw.ramp_coordinate(0.0, w) == pytest.approx(0.5 / w)
    assert tw.ramp_coordinate(1.0, w) == pytest.approx((w - 0.5) / w)
    assert tw.ramp_coordinate(-3.0, w) == tw.ramp_coordinate(0.0, w)  # u clamped
    with pytest.raises(ValueError, match="allowed an integer ≥ 2"):
        tw.fresnel_ramp(1)


def test_criterion_13_the_reflection_staircase_has_at_most_eight_levels():
    x = np.random.default_rng(1).uniform(0.0, 1.0, (20000, 3))
    x[:3] = [[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.999, 0.5, 0.15]]
    got = tw.toon_reflection(x, 0.15)
    for c in range(3):
        levels = np.unique(np.round(got[:, c], 9))
        assert len(levels) <= 8, levels
        # the levels of spec/003 eq. 7.20: k·0.15/0.85, the top one clamped to 1
        assert np.allclose(levels, np.minimum(np.arange(len(levels)) * 0.15 / 0.85, 1.0))
    # a finer Toon Value keeps more of the colour (less discretisation)
    fine = tw.toon_reflection(x, 0.05)
    assert np.abs(fine - x).mean() < np.abs(got - x).mean()
    order = np.argsort(x[:, 0])
    assert np.all(np.diff(got[order, 0]) >= 0.0)  # a staircase: never down as x goes up


def test_the_simple_type_has_three_bands_of_v_dot_n():
    nv = np.linspace(-0.2, 1.2, 10001)
    band = tw.simple_band(nv)
    assert set(np.round(band, 9)) == {0.0, 0.5, 1.0}
    assert np.all(np.diff(band) <= 0.0)  # brighter toward grazing views (small n·v)
    assert tw.simple_band(0.9) == 0.0
    assert tw.simple_band(0.5) == pytest.approx(0.5) and tw.simple_band(0.1) == pytest.approx(1.0)


def test_water_refraction_recovers_the_document_and_the_repository():
    refr = np.array([[0.9, 0.1, 0.2]])
    colour = np.array([0.1, 0.3, 0.4])
    w = np.array([0.3])
    # the document: lerp(refraction, waterColor, depth) is α = 1
    assert np.allclose(tw.water_refraction(refr, colour, 1.0, w), refr + (colour - refr) * 0.3)
    # the repository: lerp(refr, color, 0.5 + 0.5·s) is α = ½ with w = s; without fog ½
    assert np.allclose(tw.water_refraction(refr, colour, 0.5, w),
                       refr + (colour - refr) * (0.5 + 0.5 * 0.3))
    assert np.allclose(tw.water_refraction(refr, colour, 0.5, np.array([0.0])),
                       0.5 * (refr + colour))
    assert np.allclose(tw.water_refraction(refr, colour, 1.0, np.array([0.0])), refr)


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_every_fog_weight_grows_with_depth(a, b, intensity, alpha):
    near, far = 0.1, 2000.0
    lo, hi = sorted((a, b))
    for method in tw.FOG_METHODS:
        w_lo = tw.depth_fog_weight(method, lo, 1.0, 1.3, intensity, near, far)
        w_hi = tw.depth_fog_weight(method, hi, 1.0, 1.3, intensity, near, far)
        assert 0.0 <= w_lo <= w_hi + 1e-12 <= 1.0 + 1e-12
        # and so each pixel's colour moves toward the water's
        refr, colour = np.array([[1.0, 0.0, 0.0]]), np.array([0.0, 0.0, 1.0])
        d_lo = np.abs(tw.water_refraction(refr, colour, alpha, np.array([w_lo])) - colour).sum()
        d_hi = np.abs(tw.water_refraction(refr, colour, alpha, np.array([w_hi])) - colour).sum()
        assert d_hi <= d_lo + 1e-12


def test_the_fog_weights_formulas():
    near, far = 0.1, 2000.0
    d = tw.window_depth(np.array([0.5, 10.0, 300.0]), near, far)
    assert np.allclose(tw.view_depth(d, near, far), [0.5, 10.0, 300.0], rtol=1e-9)
    assert tw.view_depth(1.0, near, far) == pytest.approx(far)
    assert tw.view_depth(0.0, near, far) == pytest.approx(near)
    # the repository saturates at Linear01Depth·I·31 = 1: 60 m at I = 0.535 and far 2000 m
    z = far / (0.535 * 31.0)
    assert tw.fog_weight_repository(z / far, 0.535) == pytest.approx(1.0)
    assert tw.fog_weight_repository(0.5 * z / far, 0.535) == pytest.approx(0.5)
    # thickness: 1 − e^(−I·L); behind the water (negative thickness) nothing
    assert tw.fog_weight_thickness(2.0, 0.535) == pytest.approx(1.0 - math.exp(-1.07))
    assert tw.fog_weight_thickness(-5.0, 0.535) == 0.0
    # the document's raw GL depth is nearly 1 a few metres away: nearly flat fog there
    w5, w500 = tw.fog_weight_document(tw.window_depth(np.array([5.0, 500.0]), near, far), 0.535)
    assert 0.0 < w500 - w5 < 0.02
    with pytest.raises(ValueError, match="allowed document, repository, thickness"):
        tw.depth_fog_weight("exp", 0.5, 1.0, 1.0, 0.5, near, far)


def test_the_wave_normal_map_is_tileable_and_unit_length():
    m = tw.wave_normal_map(64)
    assert m.shape == (64, 64, 4) and m.dtype == np.float32
    n = 2.0 * m[..., :3].astype(np.float64) - 1.0
    assert np.allclose(np.linalg.norm(n, axis=-1), 1.0, atol=1e-6)
    assert n[..., 2].min() > 0.3  # slopes of waves, not cliffs
    xy = n[..., :2]
    rms = np.sqrt(np.mean(np.sum(xy * xy, -1)))
    assert 0.2 < rms < 0.45
    # across the wrap the map changes no more than between neighbours inside it
    inner = max(np.abs(np.diff(m, axis=0)).max(), np.abs(np.diff(m, axis=1)).max())
    assert np.abs(m[0] - m[-1]).max() <= inner * 1.01
    assert np.abs(m[:, 0] - m[:, -1]).max() <= inner * 1.01
    with pytest.raises(ValueError, match="allowed an integer ≥ 4"):
        tw.wave_normal_map(2)


def test_wave_normals_and_coordinates():
    flat = np.array([0.5, 0.5, 1.0, 1.0])
    assert np.allclose(tw.wave_normal(flat, flat, 1.0), [0.0, 1.0, 0.0])
    tilted = np.array([0.75, 0.5, 0.9, 1.0])  # +x in tangent space
    n0 = tw.wave_normal(tilted, tilted, 0.0)
    n1 = tw.wave_normal(tilted, tilted, 1.0)
    assert np.allclose(n0, [0.0, 1.0, 0.0])  # Wave Intensity 0: the plane's normal
    assert n1[0] > 0.4 and abs(n1[2]) < 1e-12
    uv1, uv2 = tw.wave_uvs(np.array([[12.0, -24.0]]), 20.0, 12.0, 2.0, 0.1)
    s = 0.1 * 20.0 / 20.0  # Water Speed · Unity's _Time.x
    assert np.allclose(uv1, ([1.0, 2.0] + np.array(s)) * 2.0)
    assert np.allclose(uv2, [1.0 - s, 2.0 - s])
    # the two samples move in opposite directions: crossing waves
    a1, a2 = tw.wave_uvs(np.array([[0.0, 0.0]]), 0.0, 12.0, 1.0, 0.1)
    b1, b2 = tw.wave_uvs(np.array([[0.0, 0.0]]), 10.0, 12.0, 1.0, 0.1)
    assert np.all((b1 - a1) > 0) and np.all((b2 - a2) < 0)


def test_tide_moves_the_level_by_tide_height_sin_t():
    assert tw.tide_level(0.0, 0.3, math.pi / 2) == pytest.approx(0.3)
    assert tw.tide_level(1.0, 0.3, 3 * math.pi / 2) == pytest.approx(0.7)
    assert tw.tide_level(0.0, 0.0, 1.234) == 0.0


def test_screen_uv_and_its_flip():
    uv = tw.screen_uv([[10.0, 5.0]], [100.0, 50.0], False)
    assert np.allclose(uv, [[0.1, 0.1]])
    assert np.allclose(tw.screen_uv([[10.0, 5.0]], [100.0, 50.0], True), [[0.1, 0.9]])


def test_fig_115_defaults_and_the_repository_ranges(params):
    p = params
    assert p["toon_water.water_fog_intensity"] == 0.535
    assert p["toon_water.water_speed"] == 0.089
    assert p["toon_water.tide_height"] == 0.3
    assert p["toon_water.toon_value"] == 0.128
    assert p["toon_water.depth_fog"] is True
    assert p["toon_water.type"] == "complex" and p.spec("toon_water.type").choices == (
        "simple", "complex")
    ranges = {"toon_value": (0.01, 0.2), "wave_scale": (1.0, 10.0), "water_speed": (0.01, 0.25),
              "tide_height": (0.0, 20.0), "water_fog_intensity": (0.0, 1.0),
              "wave_intensity": (0.0, 1.0)}
    for name, (lo, hi) in ranges.items():
        spec = p.spec(f"toon_water.{name}")
        assert (spec.lo, spec.hi) == (lo, hi), name
    assert p.spec("toon_water.color").kind == "color"
    assert p.spec("toon_water.color").hi > 1.0  # HDR
    with pytest.raises(NaturaError, match=r"toon_water.toon_value=0.5 .*allowed a number in "
                                          r"\[0.01, 0.2\]"):
        p.set("toon_water.toon_value", 0.5)
    with pytest.raises(NaturaError, match="allowed one of document, repository, thickness"):
        p.set("toon_water.fog_method", "linear")


def test_the_effect_declares_its_slots():
    assert ToonWater.consumes == {"image": "required", "environment": "optional",
                                  "main_light": "optional", "fog": "optional",
                                  "terrain": "optional"}
    assert ToonWater.name == "toon_water"


def test_the_plane_mesh_covers_its_reach_with_small_triangles_near_the_centre():
    v, tri = tw.plane_mesh()
    assert tri.shape == (tw.PLANE_SEGMENTS * (2 * tw.PLANE_RINGS - 1), 3)
    assert tri.min() == 0 and tri.max() == len(v) - 1
    a, b, c = (v[tri[:, k]].astype(np.float64) for k in range(3))
    cross = (b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0]
    assert np.all(cross > 0.0)  # one winding, no degenerate triangle
    # the triangles tile the circumscribed polygon: their areas add up to its area
    n = tw.PLANE_SEGMENTS
    r = 1.0 / math.cos(math.pi / n)
    assert 0.5 * cross.sum() == pytest.approx(0.5 * n * r * r * math.sin(2 * math.pi / n))
    # every point of the unit disc is inside some triangle (barycentric test)
    disc = np.random.default_rng(7).uniform(-1, 1, (3000, 2))
    disc = disc[np.hypot(*disc.T) <= 1.0]
    pts = np.concatenate([disc, 1e-3 * disc])  # and as close to the camera
    d = cross[None]
    w1 = ((b - pts[:, None])[..., 0] * (c - pts[:, None])[..., 1]
          - (b - pts[:, None])[..., 1] * (c - pts[:, None])[..., 0]) / d
    w2 = ((c - pts[:, None])[..., 0] * (a - pts[:, None])[..., 1]
          - (c - pts[:, None])[..., 1] * (a - pts[:, None])[..., 0]) / d
    inside = (w1 >= -1e-9) & (w2 >= -1e-9) & (1 - w1 - w2 >= -1e-9)
    assert inside.any(axis=1).all()
    # near the centre (within 1e-3 of the reach) the triangles are small
    near = np.hypot(*a.T) < 1e-3
    assert near.any() and np.abs(np.concatenate([b - a, c - a])[np.tile(near, 2)]).max() < 2e-3
    with pytest.raises(ValueError, match="allowed at least 1 ring and 3 segments"):
        tw.plane_mesh(0, 24)


def test_the_village_o_key_cycles_the_water_type(params):
    from app.scenes.village import VILLAGE
    from app.ui.keymap import cycle_value

    action = VILLAGE.action("O")
    assert action == "cycle:toon_water.type"
    spec = params.spec(action.split(":", 1)[1])
    assert cycle_value(spec, "complex") == "simple"
    assert cycle_value(spec, "simple") == "complex"
