"""The `planet` scene's G-buffer surfaces (spec/002-atmosphere.md §9 criteria 26–27): with no air
the composite is the plain surface colour; Phong's diffuse, ambient and specular terms on the
city's roofs; flat, tilted and default normal maps. Harness and conventions:
tests/helpers/planet.py.
"""

from __future__ import annotations

import math

import numpy as np

from app.effects.planet import effect as pfx
from tests.helpers.planet import (
    DARK_SPACE,
    NO_AIR,
    SIZE,
    box_bounds,
    camera,
    dilate,
    luminance,
    ray_boxes,
    rays,
    sun_sets,
)

# =============================================================================================
# Criteria 26–27: Phong
# =============================================================================================

CITY_TOP = dict(pos=(-36.0, 400.0, -436.0), pitch=-90.0, fov=50.0)
PHONG = {"planet.method": "shadowed", "planet.surface": "phong", **NO_AIR, **DARK_SPACE}


def roof_pixels(cam, size, sun=None):
    """Pixels of box tops (away from their edges), optionally only those no box shadows."""
    lo, hi = box_bounds()
    d = rays(cam, size).reshape(-1, 3)
    pos = np.asarray(cam.position)
    t = ray_boxes(pos, d, lo, hi)
    pts = pos + np.where(np.isfinite(t), t, 0.0)[:, None] * d
    roof = np.isfinite(t) & np.any(np.abs(pts[:, None, 1] - hi[None, :, 1]) < 0.05, axis=1)
    if sun is not None:
        roof &= ~np.isfinite(ray_boxes(pts + sun * 0.05, np.broadcast_to(sun, pts.shape), lo, hi))
    shape = (size[1], size[0])
    return roof.reshape(shape) & ~dilate(~roof.reshape(shape), 1)


def test_no_air_gives_the_plain_surface_colour(planet):
    """Criterion 27: τ = 0 and no in-scattering reproduce the G-buffer (Phong) colour within 1/255;
    with air, the composite is exactly G-buffer colour × transmittance + in-scattering."""
    cam = camera(pitch=0.0, fov=60.0)
    plain = planet.shoot(cam, SIZE, {**PHONG, **sun_sets(35.0, 180.0)})
    assert plain.mesh.sum() > 500
    assert np.abs(plain.rgb - plain.gcolour)[plain.mesh].max() < 1.0 / 255.0
    sets = {"planet.method": "shadowed", "planet.surface": "phong", **sun_sets(35.0, 180.0),
            **DARK_SPACE}
    final = planet.shoot(cam, SIZE, sets)
    t = planet.shoot(cam, SIZE, {**sets, "planet.debug_view": "out_scatter"})
    i = planet.shoot(cam, SIZE, {**sets, "planet.debug_view": "in_scatter"})
    m = final.mesh
    assert np.abs(final.rgb - (final.gcolour * t.rgb + i.rgb))[m].max() < 1e-4
    assert np.abs(final.rgb - final.gcolour)[m].mean() > 0.02     # the air does change the surfaces


def test_phong_diffuse_is_cosine_of_incidence(planet):
    """Criterion 26: diffuse ∝ max(N·L, 0) — on roofs (N = +y), k_a = k_s = 0 and geometric
    normals, the sun at 30° gives 0.5 ± 0.02 of the sun at zenith, and nothing below the
    horizon."""
    cam = camera(**CITY_TOP)
    size = (128, 128)
    sets = {**PHONG, "planet.ka": 0.0, "planet.ks": 0.0, "planet.normal_mapping": False}
    zenith = planet.shoot(cam, size, {**sets, **sun_sets(90.0, 180.0)})
    low = planet.shoot(cam, size, {**sets, **sun_sets(30.0, 180.0)})
    below = planet.shoot(cam, size, {**sets, **sun_sets(-10.0, 180.0)})
    roofs = roof_pixels(cam, size, pfx.sun_direction(30.0, 180.0))
    assert roofs.sum() > 300
    ratio = luminance(low.gcolour)[roofs] / luminance(zenith.gcolour)[roofs]
    assert np.percentile(np.abs(ratio - 0.5), 95) <= 0.02, np.percentile(ratio, [5, 50, 95])
    assert np.abs(below.gcolour[below.mesh]).max() < 1e-6


def test_phong_ambient_is_ka_times_the_texture(planet):
    cam = camera(**CITY_TOP)
    size = (96, 96)
    texture = planet.shoot(cam, size, {**PHONG, "planet.surface": "texture"})
    ambient = planet.shoot(cam, size, {**PHONG, "planet.ka": 0.5, "planet.kd": 0.0,
                                       "planet.ks": 0.0})
    m = texture.mesh
    assert m.sum() > 500
    assert np.allclose(ambient.gcolour[m], 0.5 * texture.gcolour[m], atol=1e-5)


def test_phong_specular_peaks_at_the_mirror_direction(planet):
    """k_a = k_d = 0, k_s = 1: roofs show (N·H)^n, grey, per pixel as its numpy twin from the
    G-buffer positions; the brightest roof pixel is where the view ray mirrors the sun."""
    cam = camera(**CITY_TOP)
    size = (128, 128)
    shininess = 24.0
    shot = planet.shoot(cam, size, {**PHONG, **sun_sets(90.0, 180.0), "planet.ka": 0.0,
                                    "planet.kd": 0.0, "planet.ks": 1.0,
                                    "planet.shininess": shininess,
                                    "planet.normal_mapping": False})
    roofs = roof_pixels(cam, size)
    assert roofs.sum() > 300
    rel = np.where(shot.mesh[..., None], shot.gpos[..., :3], -np.asarray(cam.forward()))
    v = -rel / np.linalg.norm(rel, axis=-1, keepdims=True)
    h = v + np.array([0.0, 1.0, 0.0])
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    twin = np.maximum(h[..., 1], 0.0) ** shininess
    assert np.abs(shot.gcolour[..., 1] - twin)[roofs].max() < 1.0 / 255.0
    mirror = np.unravel_index(np.argmax(np.where(roofs, twin, -1.0)), roofs.shape)
    peak = np.unravel_index(np.argmax(np.where(roofs, shot.gcolour[..., 1], -1.0)), roofs.shape)
    assert max(abs(mirror[0] - peak[0]), abs(mirror[1] - peak[1])) <= 1


def constant_normal_map(normal) -> np.ndarray:
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    texel = np.round(np.concatenate([n * 0.5 + 0.5, [1.0]]) * 255.0).astype(np.uint8)
    return np.broadcast_to(texel, (256, 256, 4)).copy()


def test_flat_and_tilted_normal_maps(planet, monkeypatch):
    """A flat map (0.5, 0.5, 1) gives the geometric-normal image within 1/255; a map tilted 30°
    toward the roofs' tangent (+z) changes their diffuse as N·L predicts (sun 60°, north)."""
    cam = camera(**CITY_TOP)
    size = (96, 96)
    sets = {**PHONG, **sun_sets(60.0, 0.0), "planet.ka": 0.0, "planet.ks": 0.0}
    geometric = planet.shoot(cam, size, {**sets, "planet.normal_mapping": False})
    monkeypatch.setattr(pfx, "normal_texture", lambda: constant_normal_map((0.0, 0.0, 1.0)))
    flat = planet.shoot(cam, size, {**sets, "planet.normal_mapping": True},
                        scene=planet.fresh_scene())
    assert flat.mesh.sum() > 500
    assert np.abs(flat.rgb - geometric.rgb)[flat.mesh].max() <= 1.0 / 255.0
    tilt = math.radians(30.0)
    texel = constant_normal_map((math.sin(tilt), 0.0, math.cos(tilt)))[0, 0, :3] / 255.0 * 2.0 - 1.0
    m = texel / np.linalg.norm(texel)
    monkeypatch.setattr(pfx, "normal_texture",
                        lambda: constant_normal_map((math.sin(tilt), 0.0, math.cos(tilt))))
    tilted = planet.shoot(cam, size, {**sets, "planet.normal_mapping": True},
                          scene=planet.fresh_scene())
    sun = pfx.sun_direction(60.0, 0.0)
    # roof: N = +y, tangent +z, bitangent N × T = +x → world normal (m.y, m.z, m.x)
    n_tilted = np.array([m[1], m[2], m[0]])
    predicted = max(float(n_tilted @ sun), 0.0) / float(sun[1])
    roofs = roof_pixels(cam, size, sun)
    assert roofs.sum() > 100
    ratio = luminance(tilted.gcolour)[roofs] / luminance(geometric.gcolour)[roofs]
    assert abs(predicted - 1.0) > 0.3
    assert np.percentile(np.abs(ratio - predicted), 95) < 0.02, (
        predicted, np.percentile(ratio, [5, 50, 95]))


def test_default_normal_map_changes_only_mapped_surfaces(planet):
    cam = camera(**CITY_TOP)
    size = (96, 96)
    sets = {**PHONG, **sun_sets(60.0, 0.0)}
    on = planet.shoot(cam, size, {**sets, "planet.normal_mapping": True})
    off = planet.shoot(cam, size, {**sets, "planet.normal_mapping": False})
    diff = np.abs(on.rgb - off.rgb).max(-1)
    assert diff[on.mesh].mean() > 1.0 / 255.0          # the map is not flat
    assert diff[~on.mesh].max() == 0.0                 # the analytic ground has no normal map
