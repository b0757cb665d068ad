"""The fog's numpy side (app/sim/fog.py, app/effects/fog; spec/003 §2.11, §6 criteria 33–34):
the three Unity factors at the thesis's values, the distance from Unity's clip z and its two
ends, the analytic height fog against its numeric reference (and Quílez's own form), the
FogGenerator's mapping of one intensity to both fogs, the fog's colour under the sky, the
generated texture, the plane's cutoff and scroll, where the plane lies over the island, and the
effect publishing the ``fog`` slot from its parameters."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from app.effects.fog import Fog
from app.effects.fog import plane as pl
from app.frame import FrameContext
from app.gpu.shaders import ShaderLibrary
from app.params import ParamSet
from app.sim import fog as fs
from app.sim.camera import Camera
from app.sim.daynight import Light
from tests.helpers import measures

D = np.array([1.0, 2.0, 5.0, 10.0])
FINITE = dict(allow_nan=False, allow_infinity=False)


def fog_params(*sets: str) -> ParamSet:
    params = ParamSet(Fog.declare(ShaderLibrary(None)))
    for s in sets:
        params.set_from_string(s)
    return params


# ---- criterion 33: the factors ---------------------------------------------------------------

def test_criterion_33_factors_at_the_thesis_values():
    lin = fs.FogSettings(mode="linear", start=0.0, end=10.0)
    assert fs.fog_factor(5.0, lin) == pytest.approx(0.5, abs=1e-12)  # Fig. 122a
    assert np.allclose(fs.fog_factor(D, lin), (10.0 - D) / 10.0)
    exp = fs.FogSettings(mode="exp", density=0.75)
    assert np.allclose(fs.fog_factor(D, exp), np.exp(-0.75 * D), rtol=1e-12)  # Fig. 122b
    exp2 = fs.FogSettings(mode="exp2", density=0.75)
    assert np.allclose(fs.fog_factor(D, exp2), np.exp(-(0.75 * D) ** 2), rtol=1e-12)  # 122c
    assert np.all(fs.fog_factor(D, fs.FogSettings(mode="off")) == 1.0)


def test_the_lerp_swaps_its_operands():
    """spec/003 §2.11: f decreases with distance, so colour = lerp(fogColour, colour, f)."""
    fog, obj = np.array([0.2, 0.4, 0.6]), np.array([1.0, 0.5, 0.0])
    assert np.allclose(fs.fog_apply(obj, 1.0, fog), obj)
    assert np.allclose(fs.fog_apply(obj, 0.0, fog), fog)
    assert np.allclose(fs.fog_apply(obj, 0.25, fog), 0.75 * fog + 0.25 * obj)


def test_linear_with_equal_start_and_end_is_a_step():
    f = fs.fog_factor_linear([0.0, 4.999, 5.0, 9.0], 5.0, 5.0)
    assert list(f) == [1.0, 1.0, 0.0, 0.0]


@given(st.floats(0.0, 1e4, **FINITE), st.floats(0.0, 1e4, **FINITE),
       st.sampled_from(["linear", "exp", "exp2"]), st.floats(0.0, 3.0), st.floats(0.0, 50.0),
       st.floats(0.0, 200.0))
def test_factors_lie_in_0_1_and_never_grow_with_distance(d1, d2, mode, t, s, span):
    cfg = fs.FogSettings(mode=mode, density=t, start=s, end=s + span)
    lo, hi = sorted((d1, d2))
    f_lo, f_hi = fs.fog_factor(lo, cfg), fs.fog_factor(hi, cfg)
    assert 0.0 <= f_hi <= f_lo <= 1.0


# ---- spec/003 eq. 7.24–7.26: the distance from Unity's clip z ---------------------------------

def test_the_distance_s_two_ends():
    n, f = 0.3, 250.0
    # spec/003 eq. 7.25: z_u = 0 (the far plane) gives d = far
    assert fs.fog_unity_clip_z(f, n, f) == pytest.approx(0.0, abs=1e-12)
    assert fs.fog_distance(f, n, f) == pytest.approx(f, rel=1e-12)
    # spec/003 eq. 7.26: z_u = near (the near plane) gives d = 0
    assert fs.fog_unity_clip_z(n, n, f) == pytest.approx(n, rel=1e-12)
    assert fs.fog_distance(n, n, f) == pytest.approx(0.0, abs=1e-12)
    # in between, the planar depth past the near plane, stretched by f/(f − n)
    w = np.array([1.0, 10.0, 100.0])
    assert np.allclose(fs.fog_distance(w, n, f), f * (w - n) / (f - n), rtol=1e-12)
    # behind the camera and in front of the near plane: 0, never negative
    assert np.all(fs.fog_distance([-5.0, 0.0, 0.1], n, f) == 0.0)


@given(st.floats(1e-3, 10.0), st.floats(11.0, 1e5), st.floats(0.0, 1.0))
def test_the_view_depth_inverts_the_distance(n, f, frac):
    d = frac * f
    w = fs.fog_view_depth(d, n, f)
    assert n <= w <= f * (1 + 1e-12)
    assert fs.fog_distance(w, n, f) == pytest.approx(d, rel=1e-9, abs=1e-9)


def test_uniforms_carry_the_settings():
    cfg = fs.FogSettings(mode="exp", density=0.3, start=1.0, end=9.0, colour=(0.1, 0.2, 0.3),
                         per_pixel=True, height=True, height_density=0.4, height_falloff=0.5,
                         height_base=1.5)
    u = fs.fog_uniforms(cfg, (1.0, 2.0, 3.0), 0.1, 500.0)
    assert u["uFogMode"] == 2 and u["uFogParams"] == (0.3, 1.0, 9.0)
    assert u["uFogPerPixel"] is True and u["uFogHeight"] is True
    assert u["uFogHeightParams"] == (0.4, 0.5, 1.5) and u["uFogNearFar"] == (0.1, 500.0)
    off = fs.fog_uniforms(None, (0, 0, 0), 0.1, 500.0)
    assert off["uFogMode"] == 0 and off["uFogHeight"] is False


@pytest.mark.parametrize("kw, culprit", [
    ({"mode": "fast"}, "mode"), ({"density": -0.1}, "density"), ({"density": math.nan}, "density"),
    ({"start": 5.0, "end": 4.0}, "end"), ({"height_falloff": -1.0}, "height_falloff"),
    ({"height_density": math.inf}, "height_density"), ({"colour": (1.0, math.nan, 0.0)}, "colour"),
    ({"colour": (1.0, 0.0)}, "colour"),
])
def test_bad_settings_are_one_line_errors_naming_the_culprit(kw, culprit):
    with pytest.raises(ValueError) as e:
        fs.FogSettings(**kw)
    msg = str(e.value)
    assert culprit in msg and "allowed" in msg and "\n" not in msg


# ---- the height fog (Quílez 2010) ------------------------------------------------------------

def quilez(p, o, a, b, y0):
    """Quílez's own closed form: a/b·e^(−b(o_y − y0))·(1 − e^(−b·d_y·t))/d_y, t the length."""
    ray = np.asarray(p, float) - np.asarray(o, float)
    t = np.linalg.norm(ray)
    dy = ray[1] / t
    return a / b * math.exp(-b * (o[1] - y0)) * (1.0 - math.exp(-b * dy * t)) / dy


points = st.tuples(st.floats(-300, 300), st.floats(-20, 150), st.floats(-300, 300))


@settings(max_examples=120, deadline=None)
@given(points, points, st.floats(0.0, 1.0), st.floats(0.0, 2.0), st.floats(-10.0, 30.0))
def test_height_fog_matches_its_numeric_reference(o, p, a, b, y0):
    got = fs.fog_height_transmittance(p, o, a, b, y0)
    want = fs.fog_height_reference(p, o, a, b, y0, steps=8192)
    assert 0.0 <= got <= 1.0
    assert abs(got - want) < 2e-5, (got, want)


@settings(max_examples=80, deadline=None)
@given(st.tuples(st.floats(-50, 50), st.floats(0.0, 40.0), st.floats(-50, 50)),
       st.floats(-math.pi, math.pi), st.floats(0.0, 1e-2), st.floats(0.0, 500.0),
       st.floats(1e-3, 1.0), st.floats(0.01, 2.0))
def test_grazing_rays_match_the_reference(o, azimuth, slope, length, a, b):
    """Nearly horizontal rays: u = b·|Δy| → 0 is Quílez's 0/0; the series keeps it exact."""
    d = np.array([math.cos(azimuth), slope, math.sin(azimuth)])
    p = np.asarray(o) + length * d / np.linalg.norm(d)
    got = fs.fog_height_optical_depth(p, o, a, b, 0.0)
    ref = -math.log(max(fs.fog_height_reference(p, o, a, b, 0.0, steps=4096), 1e-300))
    assert math.isfinite(got)
    assert got == pytest.approx(ref, rel=1e-6, abs=1e-12)


def test_exactly_horizontal_ray_is_a_uniform_slab():
    o, p = (0.0, 3.0, 0.0), (100.0, 3.0, 0.0)
    tau = fs.fog_height_optical_depth(p, o, 0.2, 0.5, 1.0)
    assert tau == pytest.approx(0.2 * math.exp(-0.5 * 2.0) * 100.0, rel=1e-12)


@given(points, points, st.floats(1e-3, 1.0), st.floats(0.05, 1.0), st.floats(-5.0, 10.0))
@example((0.0, 132.0, 0.0), (0.0, 131.875, 1.0), 1.0, 0.0625, 0.0)  # u = 0.0078: the series
def test_analytic_form_equals_quilez_where_his_is_well_conditioned(o, p, a, b, y0):
    ray = np.subtract(p, o)
    t = float(np.linalg.norm(ray))
    assume(t > 1.0 and abs(ray[1]) / t > 0.05 and b * abs(ray[1]) < 30.0)
    assume(b * (o[1] - y0) > -30.0)
    # below HEIGHT_SERIES_BELOW the twin takes (1 − e^(−u))/u as 1 − u/2 + u²/6, as the shader
    # does: its truncation error is under u³/24, relative (2e-8 at u = 0.0078)
    u = b * abs(ray[1])
    series = u**3 / 24.0 if u < fs.HEIGHT_SERIES_BELOW else 0.0
    assert fs.fog_height_optical_depth(p, o, a, b, y0) == pytest.approx(quilez(p, o, a, b, y0),
                                                                        rel=1e-9 + series)


def test_height_fog_edges():
    o = np.array([0.0, 2.0, 0.0])
    p = np.array([50.0, 0.5, 20.0])
    t = np.linalg.norm(p - o)
    # b = 0: a uniform fog; a = 0: none; t = 0: none
    assert fs.fog_height_optical_depth(p, o, 0.1, 0.0, 0.0) == pytest.approx(0.1 * t, rel=1e-12)
    assert fs.fog_height_transmittance(p, o, 0.0, 0.3, 0.0) == 1.0
    assert fs.fog_height_transmittance(o, o, 0.5, 0.3, 0.0) == 1.0
    # a camera far below the base: opaque, finite
    deep = fs.fog_height_transmittance(p - [0, 5000, 0], o - [0, 5000, 0], 0.1, 0.5, 0.0)
    assert deep == 0.0
    # a camera far above looking down a long ray: finite and right (no overflow at the thin end)
    hi = np.array([0.0, 2000.0, 0.0])
    got = fs.fog_height_optical_depth(p, hi, 0.1, 0.5, 0.0)
    ref = -math.log(fs.fog_height_reference(p, hi, 0.1, 0.5, 0.0, steps=1 << 18))
    assert got == pytest.approx(ref, rel=1e-3)


# ---- FogGenerator (Fig. 124) -------------------------------------------------------------------

def test_generator_maps_the_thesis_intensity():
    g = fs.FogGenerator()  # Fig. 124: 0.324, 0.264, Exponential Squared
    assert (g.intensity, g.speed, g.mode) == (0.324, 0.264, "exp2")
    assert g.global_density() == pytest.approx(0.1 * 0.324 / 2.0)
    assert g.linear_range() == pytest.approx((0.0, 30.0 * (1 - 0.324) * 2.0))
    assert fs.FogGenerator(scale=1.0).global_density() == pytest.approx(0.0324)  # the repo's
    assert float(g.plane_cutoff(4.0 * math.pi)) == pytest.approx(1.0 - 0.324)  # sin(t/8) = 1
    assert float(g.plane_cutoff(12.0 * math.pi)) == 0.0  # sin(t/8) = −1: saturated to 0
    cfg = g.settings(colour=(0.5, 0.5, 0.5), height_density=0.2)
    assert cfg.mode == "exp2" and cfg.density == pytest.approx(g.global_density())
    assert cfg.height_density == pytest.approx(0.2 * 0.324)
    assert fs.FogGenerator(intensity=0.0).settings() is None  # I = 0: both fogs off
    assert fs.FogGenerator(mode="off").settings() is None


def test_generator_intensity_drives_both_fogs():
    tex = fs.fog_texture(64)
    lo, hi = fs.FogGenerator(intensity=0.2), fs.FogGenerator(intensity=0.6)
    assert hi.global_density() > lo.global_density()
    assert hi.linear_range()[1] < lo.linear_range()[1]
    assert (hi.settings().height_density > lo.settings().height_density)
    peak = 4.0 * math.pi
    cover = [float(np.mean(fs.plane_alpha(tex[..., 3], g.plane_cutoff(peak)) > 0))
             for g in (lo, hi)]
    assert cover[1] > cover[0]
    # the half-period where sin(t/8) ≤ 0 shows all of the texture at any intensity
    assert np.array_equal(fs.plane_alpha(tex[..., 3], lo.plane_cutoff(10 * math.pi)),
                          tex[..., 3].astype(np.float64))


def test_generator_rejects_bad_input():
    for kw in ({"intensity": 1.5}, {"scale": 0.0}, {"speed": -1.0}, {"mode": "fog"},
               {"start": 10.0, "end": 5.0}):
        with pytest.raises(ValueError, match="allowed"):
            fs.FogGenerator(**kw)


# ---- the plane's cutoff, scroll and texture ---------------------------------------------------

def test_cutoff_follows_sin_time():
    t = np.linspace(0.0, 16.0 * math.pi, 400)
    c = fs.plane_cutoff(0.6, t)
    assert np.allclose(c, np.clip(0.6 * np.sin(t / 8.0), 0.0, 1.0))
    assert c.max() == pytest.approx(0.6, abs=1e-4) and c.min() == 0.0


@given(st.floats(0.0, 1.0), st.floats(0.0, 1000.0), st.floats(-math.pi, math.pi))
def test_scroll_is_linear_in_speed_times_time(speed, time, angle):
    d = (math.cos(angle), math.sin(angle))
    s = fs.plane_scroll(speed, time, d)
    assert np.allclose(s, np.array(d) * speed * time / 20.0, atol=1e-12)
    assert np.allclose(fs.plane_scroll(speed, 2 * time, d), 2 * s, atol=1e-12)


def test_texture_tiles_and_is_wispy():
    tex = fs.fog_texture(128, seed=3)
    a = tex[..., 3].astype(np.float64)
    assert tex.shape == (128, 128, 4) and tex.dtype == np.float32
    assert 0.0 <= a.min() and a.max() <= fs.TEXTURE_MAX_ALPHA + 1e-6
    assert 0.1 < (a > 0).mean() < 0.95 and a.max() > 0.6  # wisps and gaps
    # tileable: the jump across the wrap is like any step between neighbours
    inner = np.abs(np.diff(a, axis=1)).mean()
    assert np.abs(a[:, 0] - a[:, -1]).mean() < 2.0 * inner
    assert np.abs(a[0] - a[-1]).mean() < 2.0 * np.abs(np.diff(a, axis=0)).mean()
    assert np.array_equal(tex, fs.fog_texture(128, seed=3))
    assert not np.array_equal(tex, fs.fog_texture(128, seed=4))
    with pytest.raises(ValueError, match="allowed"):
        fs.fog_texture(2)


def test_centroid_follows_a_roll():
    a = fs.fog_texture(64)[..., 3]
    c0 = measures.texture_centroid(a)
    c1 = measures.texture_centroid(np.roll(a, (5, 11), axis=(0, 1)))
    shift = (c1 - c0 + 0.5) % 1.0 - 0.5
    assert np.allclose(shift, (11 / 64, 5 / 64), atol=1e-9)


# ---- the fog's colour under the sky -----------------------------------------------------------

def test_sky_colour_darkens_at_night_and_keeps_the_day_colour_at_noon():
    from app.effects.sky.effect import DEFAULT_KEYFRAMES
    from app.sim.daynight import Keyframes

    keys = Keyframes.load(DEFAULT_KEYFRAMES)
    noon = keys.ambient_at(12.0)
    assert fs.luminance(noon) == pytest.approx(fs.DAY_AMBIENT_LUMINANCE, rel=0.05)
    day = (0.58, 0.70, 0.84)
    at_noon = fs.sky_fog_colour(day, noon, tint=0.0)
    assert np.allclose(at_noon, day, rtol=0.05)
    night = fs.sky_fog_colour(day, keys.ambient_at(0.0), tint=0.3)
    assert fs.luminance(night) < 0.05 * fs.luminance(day)
    dusk = fs.sky_fog_colour(day, keys.ambient_at(18.0), tint=1.0)
    amb = keys.ambient_at(18.0)
    assert np.allclose(np.array(dusk) / fs.luminance(dusk), amb / fs.luminance(amb), rtol=1e-6)
    assert fs.sky_fog_colour(day, None) == day
    for hour in np.linspace(0, 24, 25):  # never brighter than the day colour's luminance
        assert fs.luminance(fs.sky_fog_colour(day, keys.ambient_at(hour))) <= \
            fs.luminance(day) + 1e-9


# ---- where the plane lies ---------------------------------------------------------------------

def test_plane_lies_just_above_the_plateau_and_covers_the_island():
    from app.sim.village import COAST_RADIUS, PLATEAU, Island

    island = Island()
    lay = pl.plane_layout(island, 0.35)
    assert lay.ground == pytest.approx(PLATEAU, abs=0.15)
    assert lay.y == pytest.approx(lay.ground + 0.35)
    x0, z0, x1, z1 = lay.rect
    assert x0 < -COAST_RADIUS * 0.9 and z0 < -COAST_RADIUS * 0.9
    assert x1 > COAST_RADIUS * 0.9 and z1 > COAST_RADIUS * 0.9
    m = lay.mask
    k = pl.MASK_SIZE
    assert m[k // 2, k // 2] == 1.0  # the plaza
    assert m[0, 0] == 0.0 and m[-1, -1] == 0.0  # the corners are sea
    verts, idx = pl.plane_grid(lay.rect)
    assert idx.max() < len(verts) and len(idx) % 3 == 0
    assert np.allclose(verts.min(0), (x0, z0)) and np.allclose(verts.max(0), (x1, z1))
    none = pl.plane_layout(None, 0.3)
    assert none.y == 0.3 and np.all(none.mask == 1.0)


# ---- the effect publishes the slot ------------------------------------------------------------

def frame_at(hour_light: Light | None = None, wind=None) -> FrameContext:
    f = FrameContext(size=(160, 90), camera=Camera(near=0.1, far=2000.0))
    f.main_light = hour_light
    f.wind = None if wind is None else np.asarray(wind, float)
    return f


def test_effect_publishes_the_fog_slot_from_its_parameters():
    params = fog_params("fog.mode=linear", "fog.intensity=0.5", "fog.scale=1",
                        "fog.color_from_sky=false", "fog.per_pixel=true")
    fog = Fog(None, params)
    frame = frame_at()
    fog.update(frame, 0.0)
    s = frame.fog
    assert s is not None and s.mode == "linear" and s.per_pixel is True
    assert (s.start, s.end) == pytest.approx((0.0, 15.0))
    assert s.colour == pytest.approx(params["fog.color"])
    for mode in ("exp", "exp2", "linear"):  # the panel's notes at density 0 too
        params.set("fog.mode", mode)
        params.set("fog.density", 0.0)
        fog.update(frame, 0.0)
        assert frame.fog.mode == mode and fog.panel_notes()
    params.set("fog.intensity", 0.0)
    fog.update(frame, 0.0)
    assert frame.fog is None
    params.set("fog.intensity", 0.3)
    params.set("fog.mode", "off")
    fog.update(frame, 0.0)
    assert frame.fog is None


def test_effect_defaults_are_the_thesis_figures():
    params = fog_params()
    assert params["fog.intensity"] == 0.324 and params["fog.speed"] == 0.264  # Fig. 124
    assert params["fog.mode"] == "exp2" and params["fog.density"] == 0.1  # Fig. 123
    assert tuple(fs.MODES) == Fog.python_params()[0].choices


def test_effect_colour_follows_the_sky_and_the_scroll_the_wind():
    params = fog_params("fog.speed=0.5")
    fog = Fog(None, params)
    night = Light("moon", np.array([0.0, 1.0, 0.0]), (1, 1, 1), 0.08, (0.003, 0.006, 0.018))
    frame = frame_at(night, wind=(3.0, 0.0))
    fog.update(frame, 0.0)
    assert fs.luminance(frame.fog.colour) < 0.05 * fs.luminance(params["fog.color"])
    fog.scroll = np.zeros(2)
    fog.update(frame, 2.0)
    # the texture's content moves with the wind (+x): the uv offset goes the other way
    assert fog.scroll == pytest.approx(np.mod([-0.5 * 2.0 / 20.0, 0.0], 1.0))


def test_the_scene_keys():
    from app.scenes.village import VILLAGE, VillageScene

    assert VILLAGE.bindings["F"] == "cycle:fog.mode"
    assert VILLAGE.bindings["H"] == "toggle:fog.height"
    names = [e.name for e in VillageScene.effects]
    assert names.index("fog") < min(names.index(n) for n in ("village", "grass", "toon_water"))


def test_inspector_lists_every_parameter_once():
    params = fog_params()
    fog = Fog(None, params)
    (inspector,) = fog.panel_items()
    listed = [n for names in inspector.popups.values() for n in names]
    assert sorted(listed) == sorted(p.name for p in params if p.group == "fog")
    assert inspector.popups["Fog Generator"] == ["fog.intensity", "fog.speed", "fog.mode"]
    assert inspector.textures == {}  # nothing made before the first draw
