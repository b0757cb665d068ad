"""The toon water (spec/003 §2.10) rendered: its functions through the probe
glsl/tests/toon_water_probe.frag against the numpy twins of app/sim/toon_water.py, then the
water alone over a synthetic image whose colour and depth are known at every pixel
(app.bench.village_water.WaterRig) — criteria 30 (a pure grab without waves, distortion that
grows with Wave Intensity, time, the tide), 31 (the depth fog), 32 (Fresnel), 13 (the
discretised reflection, the Simple type's 3 bands), 20 (the ramp on the GPU), the shared origin
of the grab and depth lookups and the flip switch, the depth test and write, the global fog
once, the fallbacks, and the village scene."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.bench.village_water import Backdrop, WaterRig, gradient_environment, seabed
from app.effects.toon_water.effect import FALLBACK_SKY
from app.gpu.device import Gpu
from app.render.environment import flat_environment
from app.runtime import open_session, render_frames, scene_params
from app.sim import fog as fg
from app.sim import toon_water as tw
from app.sim.camera import Camera
from app.sim.surface_maps import sample_bilinear
from tests.helpers.glsl_eval import evaluate_points

PROBE = "tests/toon_water_probe"
SIZE = (96, 54)
TOL = 2.0 / 255.0
#: 4 m above the water looking 35° down: the whole lower image is water
DOWN = Camera(position=(0.0, 4.0, 0.0), yaw=0.0, pitch=-35.0, fov=60.0, near=0.1, far=2000.0)
#: no waves, no fog, the whole refraction, no band or highlight: the water is its grab
PURE = dict(type="simple", wave_intensity=0.0, depth_fog=False, refraction=1.0,
            band_strength=0.0, highlight=0.0, output=0)


@pytest.fixture(scope="module")
def rig(module_gpu):
    r = WaterRig(module_gpu, SIZE, owner="test-water")
    yield r
    r.release()


@pytest.fixture
def water(rig):
    """The rig with every parameter at its default, then ``PURE``."""
    for p in rig.params:
        rig.params.set(p.name, p.default)
    rig.set(**PURE)
    return rig


def plane_hits(camera: Camera, size, level: float):
    """Per pixel: the ray's distance to the plane y = level (inf where it misses), the view
    depth of the hit and the ray directions."""
    d = camera.ray_directions(*size)
    o = np.asarray(camera.position)
    with np.errstate(divide="ignore"):
        t = (level - o[1]) / d[..., 1]
    t = np.where(t > 0, t, np.inf)
    return t, t * (d @ camera.forward()), d


def uniform_bed(colour, y0=-1.0, slope=(0.0, 0.12), sky=None):
    def paint(x, z):
        return np.broadcast_to(np.asarray(colour, float), x.shape + (3,))
    return dict(y0=y0, slope=slope, colour=paint, sky=colour if sky is None else sky)


# ---- the functions against their twins ------------------------------------------------------

def test_fresnel_ramp_pow5_and_bands_against_the_twins(module_gpu, rig):
    u = np.linspace(0.0, 1.0, 2001)
    pts = np.stack([u, 0 * u, 0 * u], -1)
    got = evaluate_points(module_gpu, pts, PROBE, {"uProbeMode": 0},
                          textures=[("uRamp", rig.effect.fresnel_ramp())]).astype(np.float64)
    formula = tw.fresnel_water(u)
    # criterion 20 on the GPU: the baked ramp, as the shader reads it, within 1/255
    assert np.abs(got[:, 0] - formula).max() < 0.25 / 255.0
    assert np.abs(got[:, 0] - tw.fresnel_water_ramp(tw.fresnel_ramp(), u)).max() < 2e-4
    assert np.abs(got[:, 1] - formula).max() < 1e-6
    away = np.min(np.abs((1.0 - u)[:, None] - [1 / 3, 2 / 3]), axis=1) > 1e-4
    assert np.abs(got[away, 2] - tw.simple_band(u[away])).max() < 1e-6


def test_toon_reflection_against_the_twin(module_gpu):
    x = np.random.default_rng(2).uniform(0.0, 1.3, (3000, 3))
    for toon in (0.15, 0.128):
        got = evaluate_points(module_gpu, x, PROBE, {"uProbeMode": 1, "uToonValue": toon})[:, :3]
        want = tw.toon_reflection(x, toon)
        frac = np.mod(x, toon) / toon
        away = (np.minimum(frac, 1.0 - frac) > 1e-4).all(axis=1)
        assert np.abs(got[away] - want[away]).max() < 1e-6
        for c in range(3):  # criterion 13 for step 0.15 (and 0.128: 8 levels too)
            assert len(np.unique(np.round(got[:, c], 6))) <= 8


def test_fog_weights_and_view_depth_against_the_twins(module_gpu):
    rng = np.random.default_rng(3)
    near, far, intensity = 0.1, 2000.0, 0.535
    z = np.exp(rng.uniform(np.log(0.2), np.log(1500.0), 2000))
    raw = tw.window_depth(z, near, far)
    zw = z * rng.uniform(0.3, 1.0, len(z))
    ray = rng.uniform(1.0, 3.0, len(z))
    pts = np.stack([raw, zw, ray], -1)
    got = evaluate_points(module_gpu, pts, PROBE, {"uProbeMode": 2, "uNearFar": (near, far),
                                            "uWaterFogIntensity": intensity}).astype(np.float64)
    zs = tw.view_depth(raw.astype(np.float32), near, far)  # the depth as the GPU holds it
    assert np.allclose(got[:, 3], zs, rtol=2e-3)
    assert np.abs(got[:, 0] - tw.fog_weight_document(raw, intensity)).max() < 1e-5
    assert np.abs(got[:, 1] - tw.fog_weight_repository(zs / far, intensity)).max() < 2e-3
    assert np.abs(got[:, 2] - tw.fog_weight_thickness((zs - zw) * ray, intensity)).max() < 3e-3


def test_wave_normals_against_the_twin(module_gpu, water):
    rng = np.random.default_rng(4)
    pts = np.stack([rng.uniform(-50, 50, 1500), rng.uniform(-50, 50, 1500),
                    rng.uniform(0, 100, 1500)], -1)
    u = {"uProbeMode": 3, "uWaveIntensity": 0.7, "uWaveScale": 2.5, "uWaterSpeed": 0.2,
         "uWaveTile": 9.0}
    got = evaluate_points(module_gpu, pts, PROBE, u,
                          textures=[("uNormals", water.effect.wave_normals())])[:, :3]
    nmap = tw.wave_normal_map()
    uvs = [tw.wave_uvs(p[None, :2], p[2], 9.0, 2.5, 0.2) for p in pts]  # each at its own t
    uv1 = np.concatenate([a for a, _ in uvs])
    uv2 = np.concatenate([b for _, b in uvs])
    want = tw.wave_normal(sample_bilinear(nmap, uv1), sample_bilinear(nmap, uv2), 0.7)
    err = np.linalg.norm(got - want, axis=-1)
    # llvmpipe's filter weights are fixed point (8 bits) and uv is float32 at |uv| ~ 10
    assert np.percentile(err, 99) < 1e-2 and err.max() < 2e-2, err.max()
    tilt = np.degrees(np.arccos(np.clip(want[:, 1], -1, 1)))
    assert tilt.max() > 10.0  # the waves do tilt the normal


def test_screen_uv_tide_highlight_and_reflection_against_the_twins(module_gpu):
    frag = np.array([[10.5, 5.5, 0.3], [95.5, 53.5, 2.0], [0.5, 0.5, 4.0]])
    for flip in (False, True):
        got = evaluate_points(module_gpu, frag, PROBE, {"uProbeMode": 4, "uViewport": (96.0, 54.0),
                                                 "uFlipY": flip, "uSeaLevel": 0.5,
                                                 "uTideHeight": 0.3})
        assert np.allclose(got[:, :2], tw.screen_uv(frag[:, :2], [96, 54], flip), atol=1e-6)
        assert np.allclose(got[:, 2], tw.tide_level(0.5, 0.3, frag[:, 2]), atol=1e-6)
    rng = np.random.default_rng(5)
    v = rng.normal(size=(800, 3))
    v[:, 1] = np.abs(v[:, 1])
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    n = np.array([0.2, 0.95, -0.1])
    n /= np.linalg.norm(n)
    light = np.array([0.3, 0.6, -0.74])
    light /= np.linalg.norm(light)
    got = evaluate_points(module_gpu, v, PROBE, {"uProbeMode": 5, "uNormal": tuple(n),
                                          "uLight": tuple(light), "uHighlightExponent": 40.0,
                                          "uToonValue": 0.128}).astype(np.float64)
    assert np.allclose(got[:, :3], tw.reflection_direction(v, n), atol=1e-5)
    assert got[:, 1].min() >= 0.0  # never below the horizon
    want = tw.toon_highlight(n, v, light, 40.0, 0.128)
    k = np.maximum(((light + v) / np.linalg.norm(light + v, axis=-1, keepdims=True)) @ n,
                   0.0) ** 40.0
    away = np.abs(np.mod(k, 0.128) / 0.128 - 0.5) < 0.499
    assert np.abs(got[away, 3] - want[away]).max() < 1e-5
    assert got[:, 3].max() > 0.5  # some directions are in the highlight


def test_water_refraction_against_the_twin(module_gpu):
    refr = np.random.default_rng(6).uniform(0, 2, (500, 3))
    for alpha, w in ((1.0, 0.0), (0.5, 0.3), (0.2, 1.0)):
        got = evaluate_points(module_gpu, refr, PROBE, {"uProbeMode": 6, "uColour": (0.1, 0.3, 0.4),
                                                 "uRefraction": alpha, "uWeight": w})[:, :3]
        want = tw.water_refraction(refr, (0.1, 0.3, 0.4), alpha, np.full(len(refr), w))
        assert np.allclose(got, want, atol=1e-6)


# ---- criterion 30: refraction by the grab, waves, time, tide ----------------------------------

def test_criterion_30_flat_water_is_its_grab(water):
    bd = seabed(DOWN, SIZE)
    img = water.render(DOWN, bd)
    t, _, _ = plane_hits(DOWN, SIZE, 0.0)
    on = np.isfinite(t)
    assert on.mean() > 0.5
    assert np.abs(img[..., :3] - bd.colour)[on].max() < TOL
    assert np.all(water.depth()[on] < 1.0)  # the water did draw there


def test_criterion_30_distortion_grows_with_wave_intensity(gl_ctx):
    size = (160, 90)
    own = Gpu(gl_ctx)  # a Gpu of its own: releasing its effect frees only its resources
    r = WaterRig(own, size, owner="test-water-160")
    try:
        r.set(**PURE)
        bd = seabed(DOWN, size)
        diffs = []
        for intensity in (0.0, 0.25, 0.5, 1.0):
            r.set(wave_intensity=intensity)
            img = r.render(DOWN, bd, time=3.0)
            diffs.append(float(np.abs(img[..., :3] - bd.colour).mean()))
        assert diffs[0] < 1e-5
        assert diffs[1] > 1e-4 and diffs[1] < diffs[2] < diffs[3], diffs
    finally:
        r.release()
        own.release()


def test_criterion_30_waves_move_with_time(water):
    water.set(wave_intensity=0.6, band_strength=0.35, tide_height=0.0)
    bd = seabed(DOWN, SIZE)
    a = water.render(DOWN, bd, time=10.0)
    b = water.render(DOWN, bd, time=10.0)
    c = water.render(DOWN, bd, time=14.0)
    assert np.array_equal(a, b)  # the same time: the same frame
    assert np.abs(a - c).mean() > 1e-3
    # and Water Speed is what moves them: at the same times, faster is farther from t
    water.set(water_speed=0.25)
    d = water.render(DOWN, bd, time=14.0)
    assert not np.array_equal(c, d)


@pytest.mark.parametrize("t", [math.pi / 2, 3 * math.pi / 2, 0.0])
def test_criterion_30_the_tide_moves_the_plane_along_its_normal(water, t):
    water.set(tide_height=2.0)
    bd = seabed(DOWN, SIZE, y0=-5.0)
    water.render(DOWN, bd, time=t)
    depth = water.depth()
    level = tw.tide_level(0.0, 2.0, t)
    dist, z_plane, d = plane_hits(DOWN, SIZE, float(level))
    on = np.isfinite(dist) & (depth < 1.0)
    assert on.mean() > 0.4
    z = tw.view_depth(depth, DOWN.near, DOWN.far)
    y = DOWN.position[1] + (z / (d @ DOWN.forward()))[on] * d[on][:, 1]
    assert np.abs(y - level).max() < 0.02 * max(1.0, np.abs(z[on]).max() / 20.0), (y, level)


# ---- the grab's and the depth's shared origin, and the flip switch ---------------------------

def _split_backdrop(camera, size, flip_rows=False):
    """Top half of the image: a shallow red bed 0.3 m under the water; bottom half: a deep
    green one 25 m under it (camera straight down: the water's view depth is the same on every
    row, so the expectation is symmetric)."""
    w, h = size
    t, z_plane, d = plane_hits(camera, size, 0.0)
    top = np.arange(h)[:, None] < h // 2
    top = np.broadcast_to(top, (h, w))
    if flip_rows:
        top = top[::-1]
    extra = np.where(top, 0.3, 25.0) / np.maximum(-d[..., 1], 1e-6)
    colour = np.where(top[..., None], [0.9, 0.1, 0.1], [0.1, 0.8, 0.2])
    return Backdrop(colour, (t + extra) * (d @ camera.forward())), top


def test_grab_and_depth_share_the_origin_and_the_flip_flips_both(water):
    cam = Camera(position=(0.0, 5.0, 0.0), yaw=0.0, pitch=-90.0, fov=50.0, near=0.1,
                 far=2000.0)
    water.set(depth_fog=True, fog_method="thickness", water_fog_intensity=0.3,
              color=(0.0, 0.2, 0.9))
    bd, top = _split_backdrop(cam, SIZE)
    t, zw, d = plane_hits(cam, SIZE, 0.0)
    metres = (bd.z - zw) / (d @ cam.forward())
    want = tw.water_refraction(bd.colour, (0.0, 0.2, 0.9), 1.0,
                               tw.fog_weight_thickness(metres, 0.3))
    img = water.render(cam, bd)[..., :3]
    assert np.abs(img - want).max() < TOL  # colour and depth read at one pair of coordinates
    assert np.abs(img[top] - [0.9, 0.1, 0.1]).mean() < 0.15  # shallow: the red shows
    assert np.abs(img[~top] - [0.0, 0.2, 0.9]).mean() < 0.05  # deep: water colour
    # flipped: both lookups read the mirrored row — the mirrored scene, still self-consistent
    water.set(flip_y=True)
    flipped = water.render(cam, bd)[..., :3]
    bd_m, _ = _split_backdrop(cam, SIZE, flip_rows=True)
    want_m = tw.water_refraction(bd_m.colour, (0.0, 0.2, 0.9), 1.0,
                                 tw.fog_weight_thickness((bd_m.z - zw) / (d @ cam.forward()),
                                                         0.3))
    assert np.abs(flipped - want_m).max() < TOL
    assert np.abs(flipped - img).max() > 0.5


# ---- the depth test and write ---------------------------------------------------------------

def test_the_water_is_depth_tested_and_writes_its_depth(water):
    # a post standing out of the water in the middle columns, 6 m ahead
    def post(d, t):
        w = d.shape[1]
        mask = np.zeros(d.shape[:2], bool)
        mask[:, w // 2 - 4:w // 2 + 4] = True
        return mask, np.full(d.shape[:2], 6.0), np.array([0.6, 0.3, 0.1])
    bd = seabed(DOWN, SIZE, extra=post)
    img = water.render(DOWN, bd)
    t, zw, _ = plane_hits(DOWN, SIZE, 0.0)
    in_front = bd.z < zw
    assert in_front.sum() > 20
    assert np.abs(img[..., :3] - bd.colour)[in_front].max() < 1e-6  # the post is untouched
    depth = water.depth()
    water_px = np.isfinite(t) & ~in_front
    want = tw.window_depth(zw[water_px], DOWN.near, DOWN.far)
    assert np.abs(depth[water_px] - want).max() < 1e-5  # later stages see the water


# ---- criterion 31: the depth fog ------------------------------------------------------------

@pytest.mark.parametrize("method", tw.FOG_METHODS)
def test_criterion_31_deeper_or_farther_is_closer_to_the_water_colour(water, method):
    colour = np.array([0.05, 0.3, 0.36])
    sand = [0.9, 0.8, 0.55]
    water.set(depth_fog=True, fog_method=method, color=tuple(colour))
    bd = seabed(DOWN, SIZE, **uniform_bed(sand, y0=-0.2, slope=(0.0, 0.08)))
    img = water.render(DOWN, bd)[..., :3]
    t, zw, d = plane_hits(DOWN, SIZE, 0.0)
    on = np.isfinite(t)
    raw = np.where(np.isfinite(bd.z), tw.window_depth(np.minimum(bd.z, 2000.0), 0.1, 2000.0),
                   1.0)
    zs = tw.view_depth(raw, 0.1, 2000.0)
    metric = {"document": raw, "repository": zs,
              "thickness": (zs - zw) / np.maximum(d @ DOWN.forward(), 1e-6)}[method][on]
    dist = np.linalg.norm(img[on] - colour, axis=-1)
    order = np.argsort(metric, kind="stable")
    assert np.all(np.diff(dist[order]) <= 2.5 / 255.0)  # monotonic, within 8-bit noise
    w = tw.depth_fog_weight(method, raw, zw, 1.0 / np.maximum(d @ DOWN.forward(), 1e-6),
                            0.535, 0.1, 2000.0)
    want = tw.water_refraction(np.broadcast_to(sand, img.shape), colour, 1.0, w)
    assert np.abs(img - want)[on].max() < TOL
    assert dist.max() - dist.min() > (0.002 if method == "document" else 0.3)


def test_criterion_31_without_fog_no_depth_dependence(water):
    water.set(depth_fog=False, color=(0.05, 0.3, 0.36))
    sand = [0.9, 0.8, 0.55]
    bd = seabed(DOWN, SIZE, **uniform_bed(sand, y0=-0.2, slope=(0.0, 0.08)))
    img = water.render(DOWN, bd)[..., :3]
    on = np.isfinite(plane_hits(DOWN, SIZE, 0.0)[0])
    assert np.abs(img[on] - sand).max() < 1e-5


# ---- criterion 32: Fresnel ------------------------------------------------------------------

def test_criterion_32_grazing_reflects_normal_refracts(module_gpu, water):
    env_colour = (0.2, 0.75, 0.25, 1.0)
    env = flat_environment(module_gpu, "test-water", env_colour)
    red = [0.9, 0.05, 0.05]
    water.set(type="complex", reflection_tint=False, fresnel="ramp")
    refl = tw.toon_reflection(np.array(env_colour[:3]), 0.128)
    views = {"grazing": Camera(position=(0.0, 1.5, 0.0), yaw=0.0, pitch=-1.0, fov=20.0,
                               near=0.1, far=2000.0),
             "normal": Camera(position=(0.0, 5.0, 0.0), yaw=0.0, pitch=-90.0, fov=20.0,
                              near=0.1, far=2000.0)}
    share = {}
    for name, cam in views.items():
        bd = seabed(cam, SIZE, **uniform_bed(red))
        img = water.render(cam, bd, environment=_Env(env))[..., :3]
        t, _, d = plane_hits(cam, SIZE, 0.0)
        on = np.isfinite(t)
        nv = np.clip(-d[..., 1], 0.0, 1.0)
        f = tw.fresnel_water_ramp(tw.fresnel_ramp(), nv)[..., None]
        want = np.asarray(red) + (refl - np.asarray(red)) * f
        assert np.abs(img - want)[on].max() < TOL, name
        s = ((img - red) @ (refl - red)) / np.dot(refl - red, refl - red)
        share[name] = s[on]
    assert np.median(share["grazing"]) > 0.5  # the reflection dominates
    assert share["grazing"].max() > 0.8
    assert share["normal"].max() < 0.03  # the refraction dominates (F = 0.018 head-on)
    module_gpu.free(env)


class _Env:
    def __init__(self, cube):
        self.cube = cube

    def cubemap(self, sun=True):
        return self.cube


# ---- criterion 13: the discretised reflection, the Simple type's bands -----------------------

def test_criterion_13_complex_reflection_has_at_most_eight_values_per_channel(module_gpu, water):
    env = gradient_environment(module_gpu, "test-water")
    water.set(type="complex", reflection_tint=False, wave_intensity=0.8, toon_value=0.15,
              output=1)
    cam = Camera(position=(0.0, 3.0, 0.0), yaw=30.0, pitch=-25.0, fov=90.0, near=0.1,
                 far=2000.0)
    img = water.render(cam, seabed(cam, SIZE), environment=env)[..., :3]
    t, zw, _ = plane_hits(cam, SIZE, 0.0)
    on = np.isfinite(t) & (zw < 0.99 * cam.far)  # the plane ends at the far plane
    counts = [len(np.unique(img[on][:, c])) for c in range(3)]
    assert max(counts) <= 8 and min(counts) >= 3, counts
    levels = np.minimum(np.arange(8) * 0.15 / 0.85, 1.0)
    assert np.abs(img[on][..., None] - levels).min(axis=-1).max() < 1e-5
    water.set(toon_value=0.01)  # nearly undiscretised: many more values
    fine = water.render(cam, seabed(cam, SIZE), environment=env)[..., :3]
    assert len(np.unique(fine[on][:, 0])) > 3 * counts[0]
    module_gpu.free(env.cube)


def test_criterion_13_simple_water_has_exactly_three_bands(water):
    cam = Camera(position=(0.0, 3.0, 0.0), yaw=0.0, pitch=-45.0, fov=90.0, near=0.1,
                 far=2000.0)
    water.set(wave_intensity=0.5, output=3)
    on = np.isfinite(plane_hits(cam, SIZE, 0.0)[0])
    band = water.render(cam, seabed(cam, SIZE), time=2.0)[..., 0][on]
    assert set(np.round(band * 255).astype(int)) == {0, 128, 255}
    # the image itself: a uniform bed, no fog — exactly three colours, the bands' light added
    water.set(output=0, band_strength=0.4)
    sand = np.array([0.62, 0.47, 0.31])
    img = water.render(cam, seabed(cam, SIZE, **uniform_bed(sand)), time=2.0)[..., :3][on]
    quant = np.unique(np.round(img * 255).astype(int), axis=0)
    assert len(quant) == 3, quant
    # WHITE_TOP: light 1 straight down, no ambient: the bands add 0, 0.2 and 0.4
    want = np.round((sand + 0.4 * np.array([[0.0], [0.5], [1.0]])) * 255).astype(int)
    assert np.abs(quant - want).max() <= 1


# ---- the global fog, once; the fallbacks ------------------------------------------------------

def test_the_global_fog_is_applied_once_per_fragment(water):
    fog = fg.FogSettings(mode="exp", density=0.08, colour=(0.7, 0.7, 0.75))
    bd = seabed(DOWN, SIZE)
    img = water.render(DOWN, bd, fog=fog)[..., :3]
    t, zw, _ = plane_hits(DOWN, SIZE, 0.0)
    on = np.isfinite(t)
    f = fg.fog_factor_exp(fg.fog_distance(zw[on], DOWN.near, DOWN.far), 0.08)
    want = fg.fog_apply(bd.colour[on], f, (0.7, 0.7, 0.75))
    assert np.abs(img[on] - want).max() < TOL
    assert np.abs(img[on] - bd.colour[on]).max() > 0.2  # the fog did something


def test_fallbacks_without_environment_light_or_terrain(water):
    water.set(type="complex", reflection_tint=False, output=1)
    img = water.render(DOWN, seabed(DOWN, SIZE), light=None, environment=None)[..., :3]
    on = np.isfinite(plane_hits(DOWN, SIZE, 0.0)[0])
    want = tw.toon_reflection(np.asarray(FALLBACK_SKY[:3]), 0.128)
    assert np.abs(img[on] - want).max() < 1e-5
    assert water.effect.sea_level == 0.0


def test_the_terrain_sets_the_sea_level(water):
    class Shore:
        bounds = (-10.0, -10.0, 10.0, 10.0)
        sea_level = 1.5
        revision = 0

    water.set(tide_height=0.0)
    water.render(DOWN, seabed(DOWN, SIZE, y0=-3.0), terrain=Shore())
    t, zw, _ = plane_hits(DOWN, SIZE, 1.5)
    on = np.isfinite(t)
    assert np.abs(water.depth()[on] - tw.window_depth(zw[on], 0.1, 2000.0)).max() < 1e-5


# ---- in the village --------------------------------------------------------------------------

def test_the_village_scene_shows_both_types(gl_ctx):
    cam = Camera(position=(0.0, 5.0, 75.0), yaw=0.0, pitch=-10.0, fov=60.0, near=0.1,
                 far=2000.0)
    session = open_session("village", scene_params("village", sets=[
        "village.camera=free", "fog.mode=off", "village.msaa=0"]), ctx=gl_ctx, camera=cam)
    try:
        complex_ = next(iter(render_frames(session, (96, 54), 1, 30.0)))
        session.params.set("toon_water.type", "simple")  # the scene's O key cycles it
        simple = next(iter(render_frames(session, (96, 54), 1, 30.0)))
        assert "toon_water" in {a.owner for a in session.gpu.allocations}
    finally:
        session.release()
    for img in (complex_, simple):
        assert np.isfinite(img).all() and img.min() >= 0.0
    bottom = slice(40, 54)  # the sea in front of the camera
    assert np.abs(complex_[bottom] - simple[bottom]).mean() > 0.01
    # the sea is blue-green, not the sky's grey: more blue and green than red
    sea = complex_[bottom, :, :3].reshape(-1, 3).mean(0)
    assert sea[2] > sea[0] and sea[1] > sea[0]
