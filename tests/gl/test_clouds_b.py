"""Cloud Model B (spec/000 §1.6) against spec/000 §6 criteria 17–25, on tiny targets.

Helpers are compared with their numpy twins (app/sim/clouds_b.py) through a probe
shader (glsl/tests/clouds_b_probe.frag); renders are read back as the cloud layer (rgb =
in-scattered light, a = transmittance) and as the composited target. Bakes are small (32³ /
16³ / 64²) and cached in a temporary directory. Criterion 24 (axis-aligned suns) is
tests/stability/test_clouds_b_stability.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.sim import clouds_b as twin
from app.sim.camera import Camera
from tests.helpers.clouds_b import BG, Rig, luminance
from tests.helpers.glsl_eval import evaluate_points

PROBE = "tests/clouds_b_probe"


LO, HI = np.array([-1500.0, 1000.0, -1500.0]), np.array([1500.0, 1400.0, 1500.0])


def const_texture3d(gpu, rgba, size=4):
    data = np.tile(np.asarray(rgba, np.uint8), (size, size, size, 1))
    return gpu.texture3d("probe", "const", (size, size, size), 4, data.tobytes(), dtype="f1")


def probe(clouds_b_rig: Rig, points, mode, direction=(0.0, 1.0, 0.0), volume=(128, 128, 128, 128),
          detail=(128, 128, 128, 255), coverage=128):
    """Evaluate the model at ``points`` with constant noise textures (values/255)."""
    gpu = clouds_b_rig.gpu
    vol = const_texture3d(gpu, volume)
    det = const_texture3d(gpu, detail)
    cov = gpu.texture("probe", "coverage", (4, 4), 4,
                      np.full((4, 4, 4), coverage, np.uint8).tobytes(), dtype="f1")
    uniforms = {p.uniform: clouds_b_rig.params[p.name] for p in clouds_b_rig.params if p.uniform}
    uniforms.update({"uProbeMode": mode, "uProbeDir": tuple(float(v) for v in direction),
                     "uCloudOffset": (0, 0, 0)})
    out = evaluate_points(gpu, points, PROBE, uniforms,
                          [("uVolumeNoise", vol), ("uDetailNoise", det), ("uGradientNoise", cov)])
    for t in (vol, det, cov):
        gpu.free(t)
    model = twin.ModelB.from_params(
        clouds_b_rig.params,
        volume=lambda q: np.full(np.shape(q)[:-1] + (4,), 1.0) * np.asarray(volume) / 255,
        detail=lambda q: np.full(np.shape(q)[:-1] + (3,), 1.0) * np.asarray(detail[:3]) / 255,
        coverage=lambda p: np.full(np.shape(p)[:-1], coverage / 255))
    return out, model


def test_hg_beer_powder_values_and_shader(clouds_b_rig):
    clouds_b_rig.reset()
    assert float(twin.henyey_greenstein(0.3, 0.0)) == pytest.approx(1.0 / (4.0 * math.pi))
    assert float(twin.henyey_greenstein(0.0, 0.0)) == pytest.approx(0.0796, abs=1e-4)
    assert float(twin.beer(0.0)) == 1.0 and float(twin.powder(0.0)) == 0.0
    rng = np.random.default_rng(3)
    pts = np.stack([rng.uniform(-1, 1, 300), rng.uniform(-0.95, 0.95, 300), rng.uniform(0, 6, 300)],
                   axis=-1)
    pts[:4] = [(1.0, 0.9, 0.0), (-1.0, -0.8, 0.0), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0)]
    out, _ = probe(clouds_b_rig, pts, 3)
    p = clouds_b_rig.params
    assert np.allclose(out[:, 0], twin.henyey_greenstein(pts[:, 0], pts[:, 1]), rtol=1e-4,
                       atol=1e-6)
    ph = twin.phase(pts[:, 0], p["clouds_b.forward_scattering"], p["clouds_b.back_scattering"],
                    p["clouds_b.base_brightness"], p["clouds_b.phase_factor"])
    assert np.allclose(out[:, 1], ph, rtol=1e-4)
    assert np.allclose(out[:, 2], twin.beer(pts[:, 2]), rtol=1e-5, atol=1e-7)
    assert np.allclose(out[:, 3], twin.powder(pts[:, 2]), rtol=1e-5, atol=1e-6)
    assert out[2, 2] == 1.0 and out[2, 3] == 0.0


# ---- 18: rayBoxDistance --------------------------------------------------------------------------

# origin, direction, expected (dstToBox, dstInsideBox) for the box [-1, 1]³ … scaled below
CASES = [
    ((0.0, 0.0, -5.0), (0.0, 0.0, 1.0), (4.0, 2.0)),    # outside, hitting: axis-aligned (x, y = 0)
    ((-4.0, 0.5, 0.0), (1.0, 0.0, 0.0), (3.0, 2.0)),    # outside, y and z exactly 0
    ((0.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 1.0)),     # inside: dstToBox = 0
    ((0.5, -0.2, 0.3), (0.0, 0.0, -1.0), (0.0, 1.3)),   # inside, axis-aligned
    ((0.0, 3.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0)),     # miss, parallel to the slab
    ((0.0, 0.0, -5.0), (0.0, 0.0, -1.0), (0.0, 0.0)),   # box behind the ray
    ((-5.0, -5.0, -5.0), (1.0, 1.0, 1.0), (4.0, 2.0)),  # diagonal (|d| = √3: in units of |d|)
    ((1.0, 0.0, -5.0), (0.0, 0.0, 1.0), (4.0, 0.0)),    # lying on the x = 1 wall: a miss, not a NaN
    ((0.999, 0.0, -5.0), (0.0, 0.0, 1.0), (4.0, 2.0)),  # just inside it
]


def test_ray_box_distance_cases_numpy_and_shader(clouds_b_rig):
    clouds_b_rig.reset(bounds_min=(-1.0, -1.0, -1.0), bounds_max=(1.0, 1.0, 1.0))
    for origin, direction, expected in CASES:
        got = twin.ray_box_distance((-1, -1, -1), (1, 1, 1), origin, direction)
        assert got == pytest.approx(expected, abs=1e-12), (origin, direction)
        out, _ = probe(clouds_b_rig, np.array([origin]), 2, direction)
        assert np.isfinite(out).all()
        assert out[0, :2] == pytest.approx(expected, abs=1e-5), (origin, direction)


# ---- 19: identity when empty; misses unchanged ---------------------------------------------------

def test_identity_when_empty_and_misses_unchanged(clouds_b_rig):
    cam = Camera(position=(0.0, 2.0, 2500.0), yaw=0.0, pitch=14.0, fov=70.0)
    clouds_b_rig.reset(density_threshold=-100.0)
    img, layer = clouds_b_rig.render(cam)
    assert np.abs(img - np.asarray(BG[:3])).max() <= 1.0 / 255.0
    assert (layer[..., 3] == 1.0).all() and (layer[..., :3] == 0.0).all()
    clouds_b_rig.reset()
    img, layer = clouds_b_rig.render(cam)
    dirs = cam.ray_directions(48, 27)
    miss = twin.ray_box_distance(LO, HI, np.array(cam.position), dirs)[..., 1] == 0.0
    assert miss.sum() > 100 and (~miss).sum() > 100
    assert (img[miss] == np.asarray(BG[:3], np.float32)).all()
    assert (layer[..., 3][~miss] < 0.5).any()  # and there are clouds where the rays hit


# ---- 20: depth occlusion -------------------------------------------------------------------------

def test_depth_occlusion(clouds_b_rig):
    clouds_b_rig.reset()
    cam = Camera(position=(0.0, 2.0, 1200.0), yaw=0.0, pitch=35.0, fov=70.0)
    size = (48, 27)
    near_depth = float(twin.depth_for_distance(50.0, np.array([0, 0, 1.0]), np.array([0, 0, 1.0]),
                                               cam.near, cam.far))
    far_depth = float(twin.depth_for_distance(15000.0, np.array([0, 0, 1.0]),
                                              np.array([0, 0, 1.0]), cam.near, cam.far))
    quad = (1.0, 0.0, 0.0, 1.0)

    # a red quad at 50 m on the left half, one far beyond the box on the right
    def opaque_quads(target):
        target.fbo.clear(*quad, depth=near_depth, viewport=(0, 0, size[0] // 2, size[1]))
        target.fbo.clear(*quad, depth=far_depth,
                         viewport=(size[0] // 2, 0, size[0] - size[0] // 2, size[1]))

    img, layer = clouds_b_rig.render(cam, size, prepare=opaque_quads)
    free, _ = clouds_b_rig.render(cam, size, background=quad)
    left, right = img[:, : size[0] // 2], img[:, size[0] // 2:]
    assert (left == np.asarray(quad[:3], np.float32)).all()  # nearer than the box: unchanged
    assert (layer[:, : size[0] // 2, 3] == 1.0).all()
    # beyond the box: clouds as without it
    assert np.abs(right - free[:, size[0] // 2:]).max() < 1e-5
    assert (np.abs(right - np.asarray(quad[:3])) > 0.05).any()


# ---- 21: density shape ---------------------------------------------------------------------------

def test_density_zero_at_bottom_top_and_walls(clouds_b_rig):
    clouds_b_rig.reset()
    rng = np.random.default_rng(5)
    n = 64
    x, z = rng.uniform(-1200, 1200, n), rng.uniform(-1200, 1200, n)
    y = rng.uniform(1050, 1350, n)
    pts = np.concatenate([
        np.stack([x, np.full(n, LO[1]), z], -1),
        np.stack([x, np.full(n, HI[1]), z], -1),  # h = 0, 1
        np.stack([np.full(n, LO[0]), y, z], -1), np.stack([np.full(n, HI[0]), y, z], -1),  # x walls
        np.stack([x, y, np.full(n, LO[2])], -1), np.stack([x, y, np.full(n, HI[2])], -1),  # z walls
    ])
    interior = np.stack([x, y, z], -1)
    for cov in (0, 128, 255):
        out, model = probe(clouds_b_rig, np.concatenate([pts, interior]), 0,
                           volume=(250, 250, 250, 250), coverage=cov, detail=(255, 255, 255, 255))
        assert (out[: len(pts), 0] == 0.0).all() and (out[: len(pts), 1] == 0.0).all()
        assert np.allclose(model.envelope(pts), 0.0)
        # the shader's density and envelope equal the twin's (constant noise)
        assert np.allclose(out[:, 1], model.envelope(np.concatenate([pts, interior])), atol=2e-5)
        assert np.allclose(out[:, 0], model.sample_density(np.concatenate([pts, interior])),
                           atol=2e-5)
        assert (out[len(pts):, 0] > 0.0).any()


def test_profile_bottom_heavy(clouds_b_rig):
    clouds_b_rig.reset()
    # the twin's height profile averaged over the baked coverage map (GradientSimulator, R)
    clouds_b_rig.render(Camera(position=(0, 2, 0)), (8, 8))  # bakes what is missing
    cov = clouds_b_rig.fx.bakes.baked("weather").data[..., 0].ravel() / 255.0
    h = np.linspace(0.0, 1.0, 101)
    prof = twin.ModelB.height_gradient(h[:, None], cov[None, :]).mean(axis=1)
    assert prof[h < 0.25].mean() > prof[h > 0.75].mean()
    # a rendered side view: opacity of the box's bottom quarter rows exceeds the top quarter's
    cam = Camera(position=(0.0, 1200.0, 9000.0), yaw=0.0, pitch=0.0, fov=12.0)
    size = (64, 40)
    _, layer = clouds_b_rig.render(cam, size)
    opacity = 1.0 - layer[..., 3]
    dirs = cam.ray_directions(*size)[:, size[0] // 2]
    # row heights where each row's ray crosses the box's front face (z = 1500)
    t = (HI[2] - cam.position[2]) / dirs[:, 2]
    row_y = cam.position[1] + t * dirs[:, 1]
    hp = (row_y - LO[1]) / (HI[1] - LO[1])
    rows = opacity.mean(axis=1)
    bottom, top = rows[(hp > 0.02) & (hp < 0.25)].mean(), rows[(hp > 0.75) & (hp < 0.98)].mean()
    assert bottom > top, (bottom, top)


# ---- 22: lighting --------------------------------------------------------------------------------

@pytest.mark.parametrize("direction", [(0.0, 1.0, 0.0), (1.0, 0.0, 0.0), (0.0, 0.0, -1.0),
                                       (0.6, 0.8, 0.0), (0.3, 0.5, -0.81)])
def test_light_at_pos_matches_twin_and_floor(clouds_b_rig, direction):
    clouds_b_rig.reset()
    d = np.asarray(direction) / np.linalg.norm(direction)
    rng = np.random.default_rng(11)
    pts = np.stack([rng.uniform(-1500, 1500, 200), rng.uniform(1000, 1400, 200),
                    rng.uniform(-1500, 1500, 200)], -1)
    out, model = probe(clouds_b_rig, pts, 1, d, volume=(240, 240, 240, 240),
                       detail=(200, 200, 200, 255), coverage=160)
    expected = model.light_at_pos(pts, d)
    dark = clouds_b_rig.params["clouds_b.darkness_threshold"]
    assert np.isfinite(out[:, 0]).all()
    assert (out[:, 0] >= dark - 1e-6).all() and (expected >= dark).all()
    assert np.allclose(out[:, 0], expected, rtol=2e-4, atol=2e-5)
    assert expected.min() < 0.5  # the light march does darken


def _light_per_opacity(layer, mask):
    opacity = 1.0 - layer[..., 3]
    return luminance(layer[..., :3])[mask].sum() / max(opacity[mask].sum(), 1e-9)


def test_sun_facing_side_brighter(clouds_b_rig):
    # side view from the south, sun low in the east (+x, the right of the image); phase made flat
    clouds_b_rig.reset(forward_scattering=0.0, back_scattering=0.0, density_threshold=-4.0)
    cam = Camera(position=(0.0, 1200.0, 9000.0), yaw=0.0, pitch=0.0, fov=22.0)
    size = (64, 24)
    _, layer = clouds_b_rig.render(cam, size, light=(math.cos(0.2), math.sin(0.2), 0.0))
    half = size[0] // 2
    left = np.zeros(layer.shape[:2], bool)
    left[:, :half] = True
    assert (1.0 - layer[..., 3])[left].sum() > 1.0 and (1.0 - layer[..., 3])[~left].sum() > 1.0
    assert _light_per_opacity(layer, ~left) > 1.1 * _light_per_opacity(layer, left)


def test_forward_scattering_brighter_toward_sun(clouds_b_rig):
    clouds_b_rig.reset(forward_scattering=0.8, back_scattering=0.0)
    sun = np.array([math.cos(math.radians(20)), math.sin(math.radians(20)), 0.0])
    size = (40, 24)
    values = {}
    for name, yaw in (("toward", 90.0), ("away", 270.0)):
        cam = Camera(position=(0.0, 2.0, 0.0), yaw=yaw, pitch=35.0, fov=50.0)
        _, layer = clouds_b_rig.render(cam, size, light=sun)
        values[name] = _light_per_opacity(layer, np.ones(layer.shape[:2], bool))
        assert (1.0 - layer[..., 3]).mean() > 0.05
    assert values["toward"] > 1.2 * values["away"], values


# ---- 23: early exit ------------------------------------------------------------------------------

def test_early_exit_transmittance(clouds_b_rig):
    absorb, step = 0.05, 4.0
    clouds_b_rig.reset(density_threshold=3.0, light_absortion_cloud=absorb, fixed_step_size=step,
              num_steps_light=2)
    # every ray crosses the layer
    cam = Camera(position=(0.0, 2.0, 0.0), yaw=0.0, pitch=90.0, fov=40.0)
    _, layer = clouds_b_rig.render(cam, (24, 16))
    t = layer[..., 3]
    # one step multiplies T by exp(−ρ·step·absorb) with ρ ≤ max volume density (1 + 0.3 here)
    floor = 0.01 * math.exp(-1.3 * step * absorb)
    assert np.isfinite(t).all() and t.min() >= floor - 1e-6
    assert t.max() < 0.0101  # every ray went dense and stopped at the threshold, not far below it


# ---- 25: wind drift; speed 0 gives identical frames ----------------------------------------------

def test_wind_moves_mask_along_wind_and_zero_speed_is_static(clouds_b_rig):
    # toward +x (east)
    clouds_b_rig.reset(wind_speed=20.0, wind_direction=90.0, density_threshold=-4.5)
    # looking down, +x to the right
    cam = Camera(position=(0.0, 9000.0, 0.0), yaw=0.0, pitch=-90.0, fov=12.0)
    size = (48, 48)
    _, a = clouds_b_rig.render(cam, size, time=0.0)
    _, b = clouds_b_rig.render(cam, size, time=12.0)  # 240 m east: ~7 px at this distance
    ma, mb = 1.0 - a[..., 3], 1.0 - b[..., 3]
    ys, xs = np.mgrid[0:size[1], 0:size[0]]
    ca = np.array([(ma * xs).sum(), (ma * ys).sum()]) / ma.sum()
    cb = np.array([(mb * xs).sum(), (mb * ys).sum()]) / mb.sum()
    shift = cb - ca
    # clouds enter and leave the view at its borders, so the centroid moves less than the
    # field; it must still move along the wind (+x) and not across it
    assert shift[0] > 0.3 and abs(shift[1]) < 0.5 * shift[0], shift
    # phase correlation finds the field's shift: the expected pixels
    f = np.fft.fft2(ma - ma.mean()) * np.conj(np.fft.fft2(mb - mb.mean()))
    corr = np.fft.ifft2(f / np.maximum(np.abs(f), 1e-12)).real
    dy, dx = np.unravel_index(np.argmax(corr), corr.shape)
    dx = -((dx + size[0] // 2) % size[0] - size[0] // 2)
    dy = -((dy + size[1] // 2) % size[1] - size[1] // 2)
    expected_px = 240.0 / (2.0 * (9000.0 - 1200.0) * math.tan(math.radians(6.0))) * size[1]
    assert abs(dx - expected_px) <= 1.5 and abs(dy) <= 1, (dx, dy, expected_px)
    clouds_b_rig.params.set("clouds_b.wind_speed", 0.0)
    _, c = clouds_b_rig.render(cam, size, time=0.0)
    _, d = clouds_b_rig.render(cam, size, time=37.0)
    assert (c == d).all()


# ---- beyond the thesis: the weather map's coverage and aerial perspective --------------------

def test_weather_coverage_thins_where_the_map_is_low_as_the_twin(clouds_b_rig):
    """clouds_b.weather_coverage = 1: the coverage map scales the base shape by
    smoothstep(0.3, 0.7, map) — nothing where the map is low, the thesis where it is high; the
    shader's density equals the twin's (constant noise)."""
    clouds_b_rig.reset(weather_coverage=1.0, density_threshold=-2.0)
    rng = np.random.default_rng(3)
    n = 24
    pts = np.stack([rng.uniform(-1200, 1200, n), rng.uniform(1100, 1300, n),
                    rng.uniform(-1200, 1200, n)], -1)
    dens = {}
    for cov in (40, 128, 230):
        out, model = probe(clouds_b_rig, pts, 0, volume=(250, 250, 250, 250), coverage=cov,
                           detail=(255, 255, 255, 255))
        assert np.allclose(out[:, 0], model.sample_density(pts), atol=2e-5), cov
        dens[cov] = out[:, 0]
    assert (dens[40] == 0.0).all()
    assert (dens[128] < dens[230]).all() and (dens[230] > 0.0).all()
    assert float(twin.ModelB.weather_cover(0.1, 0.0)) == 1.0  # off: the thesis


def test_haze_fades_far_clouds_into_the_background(clouds_b_rig):
    """clouds_b.haze_distance > 0 (no probe: the faded part turns transparent): the far cloud
    field lets more background through and scatters less light than without the haze; 0 is the
    thesis exactly."""
    cam = Camera(position=(0.0, 2.0, 1400.0), yaw=0.0, pitch=8.0, fov=60.0)
    clouds_b_rig.reset(density_threshold=-4.0)
    _, clear = clouds_b_rig.render(cam)
    clouds_b_rig.params.set("clouds_b.haze_distance", 1500.0)
    _, hazy = clouds_b_rig.render(cam)
    cloudy = clear[..., 3] < 0.9
    assert cloudy.sum() > 20
    assert (hazy[..., 3] >= clear[..., 3] - 1e-6).all()
    assert hazy[..., 3][cloudy].mean() > clear[..., 3][cloudy].mean() + 0.05
    assert hazy[..., :3][cloudy].mean() < clear[..., :3][cloudy].mean()
    assert np.isfinite(hazy).all()
