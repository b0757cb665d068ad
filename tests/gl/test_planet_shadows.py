"""The `planet` scene's shadow map (spec/002-atmosphere.md §9 criteria 22–26): an orthographic
map re-rendered only when the sun moves, box shadows against an analytic ray–box footprint of
``planet_geometry.boxes``, no acne, the filter across an edge and the light shafts, against a
numpy twin of ``glsl/planet/shadow.glsl`` that reads the rendered map back. Harness and
conventions: tests/helpers/planet.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.effects.planet import effect as pfx
from app.render import shadows
from app.runtime import Session, render_frames
from app.sim import atmosphere as atm
from tests.helpers.planet import (
    DARK_SPACE,
    MODEL,
    NO_AIR,
    SIZE,
    SMALL,
    box_bounds,
    camera,
    dilate,
    ground_view,
    luminance,
    planet_centred,
    ray_boxes,
    rays,
    sun_sets,
)

# ---- the shadow map, read back: twin of glsl/planet/shadow.glsl ----------------------------------

def shadow_depths(effect) -> np.ndarray:
    tex = effect._shadow.value[0]  # the shadow map's depth texture
    n = tex.size[0]
    return np.frombuffer(tex.read(), dtype=np.float32).reshape(n, n).astype(np.float64)


def light_coords(effect, local) -> np.ndarray:
    m = pfx.light_view_proj(effect.sun_dir)
    clip = np.asarray(local, dtype=np.float64) @ m[:3, :3].T + m[:3, 3]
    return clip * 0.5 + 0.5


def visibility_point(effect, depths, local, bias) -> np.ndarray:
    """``ShadowVisibilityPoint``: one bilinear comparison; lit outside the map's box."""
    p = light_coords(effect, local)
    inside = np.all((p >= 0.0) & (p <= 1.0), -1)
    return np.where(inside, shadows.compare_bilinear(depths, p[..., :2], p[..., 2] - bias), 1.0)


def visibility_filtered(effect, depths, local, bias) -> np.ndarray:
    """``ShadowVisibility`` with the filter on: the shared PCF (common/shadow_pcf.glsl: 5×5
    Gaussian, σ = 1 texel, of bilinear comparisons), through its twin in app/render/shadows.py."""
    p = light_coords(effect, local)
    inside = np.all((p >= 0.0) & (p <= 1.0), -1)
    return np.where(inside, shadows.pcf_visibility(depths, p[..., :2], p[..., 2] - bias), 1.0)


# =============================================================================================
# Criterion 22: the shadow map
# =============================================================================================

def test_shadow_map_is_orthographic_and_rerenders_only_when_the_sun_moves(planet):
    m = pfx.light_view_proj(pfx.sun_direction(35.0, 180.0))
    assert np.allclose(m[3], [0.0, 0.0, 0.0, 1.0])          # orthographic: w = 1
    scene = planet.fresh_scene()
    effect = scene.effect("planet")
    planet.apply({"planet.method": "shadowed", "planet.shadow_map_size": 256})
    scene.camera = camera()
    frames = render_frames(Session(planet.gpu, scene, planet.params), (32, 18), frames=23)
    for _ in range(10):
        next(frames)
    assert effect.shadow_passes == 1
    planet.params.set("planet.sun_elevation", 40.0)
    for _ in range(10):
        next(frames)
    assert effect.shadow_passes == 2
    planet.params.set("planet.shadow_map_size", 512)      # what it depends on besides the sun
    for _ in range(3):
        next(frames)
    assert effect.shadow_passes == 3
    frames.close()


@pytest.mark.parametrize("elevation,azimuth", [(35.0, 180.0), (8.0, 70.0), (80.0, 300.0)])
def test_caster_box_holds_every_caster(elevation, azimuth):
    """Where the map is read at all (planet/shadow.glsl's uShadowCasterBox, uShadowCasterDepth):
    every caster vertex lies inside the box, at least the filter's reach and a texel from its
    edges, and no nearer the sun than its depth; outside, the comparisons pass anyway."""
    sun = pfx.sun_direction(elevation, azimuth)
    size = 1024
    pts = pfx.caster_points(MODEL.bottom_radius)
    (x0, y0, x1, y1), depth = pfx.caster_box(pts, sun, size)
    m = pfx.light_view_proj(sun)
    p = (pts @ m[:3, :3].T + m[:3, 3]) * 0.5 + 0.5
    reach = (shadows.PCF_RADIUS + 1) / size
    assert np.all(p[:, 0] >= x0 + reach) and np.all(p[:, 0] <= x1 - reach)
    assert np.all(p[:, 1] >= y0 + reach) and np.all(p[:, 1] <= y1 - reach)
    assert np.all(p[:, 2] > depth) and p[:, 2].min() - depth < 1e-4


def test_open_ground_is_lit_lambert_by_the_shadowed_method(planet):
    """The universe is not in the shadow pass: open ground away from the meshes gets the full
    Lambert term — with no air, lit/ambient-only = (k_a + k_d cos 45°) / k_a per pixel."""
    cam = camera(pos=(0.0, 300.0, 600.0), pitch=-90.0, fov=40.0)   # south of the city: open ground
    sets = {"planet.method": "shadowed", **sun_sets(45.0, 180.0), **NO_AIR, **DARK_SPACE}
    lit = planet.shoot(cam, SMALL, sets)
    ambient = planet.shoot(cam, SMALL, {**sets, "planet.kd": 0.0})
    assert not lit.mesh.any()
    ka, kd = planet.defaults["planet.ka"], planet.defaults["planet.kd"]
    ratio = luminance(lit.rgb) / luminance(ambient.rgb)
    assert np.allclose(ratio, (ka + kd * math.sin(math.radians(45.0))) / ka, rtol=5e-3)


# =============================================================================================
# Criterion 23: surface shadows — footprint and acne
# =============================================================================================

def shadow_case(planet, k, sun_el, sun_az, sets, size=(128, 128), altitude=250.0, fov=30.0):
    """Camera straight above box k's shadow (no air, no sky): the shot and the analytic masks."""
    lo, hi = box_bounds()
    sun = pfx.sun_direction(sun_el, sun_az)
    away = -np.array([sun[0], 0.0, sun[2]]) / math.hypot(sun[0], sun[2])
    centre = 0.5 * (lo[k] + hi[k]) + away * 0.5 * hi[k, 1] / math.tan(math.radians(sun_el))
    cam = camera(pos=(centre[0], altitude, centre[2]), pitch=-90.0, fov=fov)
    shot = planet.shoot(cam, size, {"planet.method": "shadowed", **sun_sets(sun_el, sun_az),
                                    **NO_AIR, **DARK_SPACE, **sets})
    ground, shadow, pts = ground_view(cam, size, sun, lo, hi)
    own = np.isfinite(ray_boxes(pts.reshape(-1, 3), np.broadcast_to(sun, (pts.size // 3, 3)),
                                lo[k:k + 1], hi[k:k + 1])).reshape(ground.shape) & ground
    return shot, ground, shadow, own


def test_box_shadow_footprint_matches_the_analytic_one(planet):
    """Criterion 23: sun 45°, the largest map (8192², 4.2 m texels), the city's widest tall box
    (25 × 21 × 90 m): ground pixels darker than 0.6 × the lit-ground mean against the analytic
    ray–box footprint, IoU ≥ 0.9, over the neighbourhood of that box's shadow. Unfiltered (nearest)
    comparison: the footprint is a hard-edged polygon (the filter is criterion 24's)."""
    lo, hi = box_bounds()
    k = int(np.argmax((hi[:, 0] - lo[:, 0]) * (hi[:, 1] - lo[:, 1])))
    shot, ground, shadow, own = shadow_case(planet, k, 45.0, 135.0, {"planet.shadow_map_size": 8192,
                                                                     "planet.shadow_filter": False})
    lum = luminance(shot.rgb)
    lit_mean = lum[ground & ~dilate(shadow, 3)].mean()
    region = ground & dilate(own, 6) & ~(dilate(shadow & ~own, 6))
    dark = (lum < 0.6 * lit_mean) & region
    footprint = own & region
    assert footprint.sum() > 1000
    iou = (dark & footprint).sum() / (dark | footprint).sum()
    assert iou >= 0.9, iou


@pytest.mark.parametrize("size_map", [4096, 8192])
def test_box_shadow_shows_on_the_ground_with_the_filter(planet, size_map):
    """Criterion 23 with the thesis's filtered variant, at the scene's default map (4096², 8.3 m
    texels) and the largest (8192², 4.2 m): at least half of the widest tall box's analytic
    footprint is dark (< 0.6 × lit ground) and nothing is dark farther than the filter's reach
    (3 texels) from the footprints."""
    lo, hi = box_bounds()
    k = int(np.argmax((hi[:, 0] - lo[:, 0]) * (hi[:, 1] - lo[:, 1])))
    shot, ground, shadow, own = shadow_case(planet, k, 45.0, 135.0,
                                            {"planet.shadow_map_size": size_map})
    lum = luminance(shot.rgb)
    lit_mean = lum[ground & ~dilate(shadow, 6)].mean()
    dark = (lum < 0.6 * lit_mean) & ground
    pixel_m = 2.0 * 250.0 * math.tan(math.radians(15.0)) / 128
    reach = int(math.ceil(3 * 2 * pfx.SHADOW_HALF / size_map / pixel_m))
    assert not np.any(dark & ~dilate(shadow, reach))
    assert (dark & own).sum() >= 0.5 * own.sum(), ((dark & own).sum(), own.sum())


def test_no_shadow_acne_on_lit_ground_and_roofs(planet):
    """Lit surfaces (away from the analytic shadows and box edges): < 0.5 % of pixels darker than
    0.8 × their mean — the ground (not in the map) and the roofs (in it, with the default bias)."""
    lo, hi = box_bounds()
    cam = camera(pos=(-36.0, 600.0, -440.0), pitch=-90.0, fov=40.0)
    size = (128, 128)
    sun = pfx.sun_direction(45.0, 135.0)
    shot = planet.shoot(cam, size, {"planet.method": "shadowed", **sun_sets(45.0, 135.0), **NO_AIR,
                                    **DARK_SPACE, "planet.normal_mapping": False, "planet.ks": 0.0})
    ground, shadow, _ = ground_view(cam, size, sun, lo, hi)
    lum = luminance(shot.rgb)
    margin = dilate(shadow | ~ground, 3)
    lit = ground & ~margin
    assert lit.sum() > 5000
    assert (lum[lit] < 0.8 * lum[lit].mean()).mean() < 0.005
    # roofs: pixels of a box top (normal +y) that no box shadows; the texture varies, so compare
    # with the ambient-only image: (k_a + k_d cos 45°) / k_a everywhere on lit roofs
    ambient = planet.shoot(cam, size, {"planet.method": "shadowed", **sun_sets(45.0, 135.0),
                                       **NO_AIR, **DARK_SPACE, "planet.normal_mapping": False,
                                       "planet.ks": 0.0, "planet.kd": 0.0})
    d = rays(cam, size).reshape(-1, 3)
    t = ray_boxes(np.asarray(cam.position), d, lo, hi)
    pts = np.asarray(cam.position) + np.where(np.isfinite(t), t, 0.0)[:, None] * d
    roof = np.isfinite(t) & np.any(np.abs(pts[:, None, 1] - hi[None, :, 1]) < 0.05, axis=1)
    roof_lit = roof & ~np.isfinite(ray_boxes(pts + sun * 0.05, np.broadcast_to(sun, pts.shape), lo,
                                             hi))
    roof_lit = roof_lit.reshape(ground.shape) & ~dilate(~roof.reshape(ground.shape), 1)
    assert roof_lit.sum() > 200
    ratio = luminance(shot.rgb)[roof_lit] / luminance(ambient.rgb)[roof_lit]
    ka, kd = planet.defaults["planet.ka"], planet.defaults["planet.kd"]
    expected = (ka + kd * math.sin(math.radians(45.0))) / ka
    assert np.median(ratio) == pytest.approx(expected, rel=0.01)
    assert (ratio < 0.8 * expected).mean() < 0.005


# =============================================================================================
# Criterion 24 and 26 (min): the filter across a shadow edge, against the twin of shadow.glsl
# =============================================================================================

def edge_case(planet, filtered: bool, sun_el: float = 45.0):
    """The widest tall box's shadow on the ground seen from 200 m straight above (0.84 m pixels),
    8192² map (4.2 m texels, 5 pixels each), no air."""
    lo, hi = box_bounds()
    k = int(np.argmax((hi[:, 0] - lo[:, 0]) * (hi[:, 1] - lo[:, 1])))
    sun = pfx.sun_direction(sun_el, 135.0)
    away = -np.array([sun[0], 0.0, sun[2]]) / math.hypot(sun[0], sun[2])
    centre = 0.5 * (lo[k] + hi[k]) + away * 0.5 * hi[k, 1] / math.tan(math.radians(sun_el))
    cam = camera(pos=(centre[0], 200.0, centre[2]), pitch=-90.0, fov=30.0)
    size = (128, 128)
    sets = {"planet.method": "shadowed", **sun_sets(sun_el, 135.0), **NO_AIR, **DARK_SPACE,
            "planet.shadow_filter": filtered, "planet.shadow_map_size": 8192}
    ambient = planet.shoot(cam, size, {**sets, "planet.kd": 0.0})
    shot = planet.shoot(cam, size, sets, fresh=True)       # its shadow map stays for the twins
    ground, shadow, pts = ground_view(cam, size, sun, lo, hi)
    return shot, ambient, ground, shadow, pts, sun


@pytest.mark.parametrize("filtered", [True, False])
def test_shadow_filter_levels_across_the_edge(planet, filtered):
    """Criterion 24: across a shadow edge, the Gaussian-weighted bilinear filter gives ≥ 3 distinct
    intermediate 8-bit levels over ≥ 2 pixels of a row; the nearest, unfiltered variant a step
    with at most one transition pixel per row."""
    shot, ambient, ground, shadow, _, _ = edge_case(planet, filtered)
    level = np.round(shot.display * 255.0)[..., 1]
    lit_level = np.median(level[ground & ~dilate(shadow, 12)])
    dark_level = np.median(level[ground & shadow & ~dilate(~shadow | ~ground, 12)])
    assert lit_level - dark_level > 25, (lit_level, dark_level)
    widths, distinct = [], []
    for row in range(level.shape[0]):
        g = ground[row]
        if g.sum() < level.shape[1] * 0.9 or not shadow[row].any() or shadow[row].all():
            continue
        mid = g & (level[row] > dark_level + 1) & (level[row] < lit_level - 1)
        widths.append(int(mid.sum()))
        distinct.append(len(set(level[row][mid].tolist())))
    assert len(widths) > 20
    if filtered:
        assert np.median(distinct) >= 3 and np.median(widths) >= 2, (np.median(distinct),
                                                                     np.median(widths))
    else:
        assert max(widths) <= 1 * 2, widths     # a row crosses the shadow twice: ≤ 1 pixel per edge


def test_ground_shading_is_min_of_shadow_and_lambert(planet):
    """Criterion 26 (shadowed diffuse = min(shadow, diffuse)), per pixel on the ground against the
    numpy twin of the filtered visibility read from the shadow map: with the sun at 30°, N·L = 0.5,
    so the penumbra where V > 0.5 stays fully lit — a product V × N·L would darken it."""
    shot, ambient, ground, shadow, pts, sun = edge_case(planet, True, sun_el=30.0)
    depths = shadow_depths(planet.effect)
    vis = visibility_filtered(planet.effect, depths, pts, 0.0)
    ka, kd = planet.defaults["planet.ka"], planet.defaults["planet.kd"]
    nl = math.sin(math.radians(30.0))
    base = luminance(ambient.rgb) / ka                   # the ground's albedo (luminance)
    with_min = base * (ka + kd * np.minimum(vis, nl))
    with_product = base * (ka + kd * vis * nl)
    got = luminance(shot.rgb)
    err = np.abs(got - with_min)[ground]
    assert np.percentile(err, 99) < 1.0 / 255.0 and err.mean() < 0.2 / 255.0
    # the test can tell them apart
    assert np.abs(got - with_product)[ground].max() > 10.0 / 255.0


# =============================================================================================
# Criterion 25: light shafts
# =============================================================================================

def test_light_shafts_dim_rays_through_the_mountain_shadow(planet):
    """Low sun (10°) behind the mountains, camera looking at it past them; in-scattering on black
    with V(P) (method 3) and with V ≡ 1 (method 2), Phong surfaces for both. Rays that cross the
    shadow volume (found with the read-back map, 600 samples per ray) are darker by ≥ 5 % on
    average; rays that never meet it differ by < 1/255."""
    cam = camera(yaw=0.0, pitch=4.0, fov=60.0)
    size = SIZE
    sets = {**sun_sets(10.0, 0.0), **DARK_SPACE, "planet.surface": "phong",
            "planet.debug_view": "in_scatter"}
    shafts = planet.shoot(cam, size, {**sets, "planet.method": "shadowed"}, fresh=True)
    depths = shadow_depths(planet.effect)
    plain = planet.shoot(cam, size, {**sets, "planet.method": "lut"})
    d = rays(cam, size).reshape(-1, 3)
    seg = atm.atmosphere_segment(planet_centred(cam), d, None, MODEL)
    end = np.where(shafts.mesh.reshape(-1),
                   np.linalg.norm(shafts.gpos[..., :3], axis=-1).reshape(-1), seg.t1)
    pos = np.asarray(cam.position)
    bias = planet.defaults["planet.shadow_bias"]
    sub = np.arange(0, len(d), 3)
    frac = (np.arange(600) + 0.5) / 600
    min_v = np.ones(len(sub))
    for a in range(0, len(sub), 1500):
        s = sub[a:a + 1500]
        t = np.minimum(end[s], 100_000.0)[:, None] * frac
        min_v[a:a + 1500] = visibility_point(planet.effect, depths, pos + d[s, None] * t[..., None],
                                             bias).min(1)
    crossing, free = sub[min_v < 0.5], sub[min_v >= 1.0]
    assert len(crossing) > 300 and len(free) > 1000
    a_lum = luminance(shafts.rgb.reshape(-1, 3))
    b_lum = luminance(plain.rgb.reshape(-1, 3))
    assert a_lum[crossing].mean() <= 0.95 * b_lum[crossing].mean(), (
        a_lum[crossing].mean() / b_lum[crossing].mean())
    assert np.abs(shafts.rgb.reshape(-1, 3)[free]
                  - plain.rgb.reshape(-1, 3)[free]).max() < 1.0 / 255.0
