"""The shared shadow module on the GPU (spec/003 §2.8, criteria 22–26): biases against the exact
visibility of a cube on a plane, the stable fit, the filters' levels, the point light's faces,
dithered semitransparent shadows and degenerate lights and cameras."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from app.errors import ParamError
from app.gpu.device import Gpu
from app.render.shadow_maps import MeshCasters, ShadowProbe, ShadowSet
from app.render.shadows import ShadowSettings
from app.runtime import scene_params
from app.sim import surfaces_scene as ss
from app.sim.camera import Camera
from tests.helpers.images import read_face

LIGHT = np.array([0.5, 1.0, 0.3]) / np.linalg.norm([0.5, 1.0, 0.3])
SCENE = ss.SurfacesScene(boxes=[ss.Box("floor", (0, -0.05, 0), (4, 0.05, 4)),
                                ss.Box("cube", (0, 0.5, 0), (0.5, 0.5, 0.5))])
BASE = ShadowSettings(map_size=512, cascades=0, filter="hard", fixed_radius=5.0,
                      fixed_centre=(0.0, 0.5, 0.0))


@pytest.fixture(scope="module")
def rig(gl_ctx):
    gpu = Gpu(gl_ctx)
    cas = MeshCasters(gpu, "shadow-test", [(ss.mesh(o), 0, 1.0, 0.5, None) for o in SCENE.boxes])
    yield gpu, cas, ShadowSet(gpu, "shadow-test"), ShadowProbe(gpu, "shadow-test")
    gpu.release()


def camera():
    return Camera(position=(0, 3, 6), yaw=0, pitch=-25, fov=60, near=0.1, far=100)


def floor_points(n=160, half=3.9):
    xs = np.linspace(-half, half, n)
    x, z = np.meshgrid(xs, xs)
    p = np.stack([x, np.zeros_like(x), z], -1)
    return p, np.tile([0.0, 1.0, 0.0], p.shape[:-1] + (1,))


def sun(rig, settings, light=LIGHT, cam=None, points=None):
    gpu, cas, shadows, probe = rig
    cam = cam or camera()
    shadows.sun.render(cas, cam, 1.0, light, settings)
    p, n = points if points is not None else floor_points()
    depth = (p - np.asarray(cam.position)) @ cam.forward()
    return probe.visibility(shadows, p, n, depth)


def exact(points, light=LIGHT):
    p = points.reshape(-1, 3) + [0, 1e-3, 0]
    return ss.occluded(SCENE, p, np.tile(light, (len(p), 1))).reshape(points.shape[:-1])


def test_bias_acne_clean_and_peter_panning(rig):
    p, _ = floor_points()
    truth = exact(p)
    rates = {}
    for label, nb, lb in (("none", 0.0, 0.0), ("thesis", 0.3, 0.01), ("panning", 0.3, 0.6)):
        v, _ = sun(rig, replace(BASE, normal_bias=nb, linear_bias=lb))
        rates[label] = ((v < 0.5) & ~truth).mean(), ((v >= 0.5) & truth).mean()
    assert rates["none"][0] > 0.2  # acne: lit floor shadowed
    assert rates["thesis"][0] < 0.005 and rates["thesis"][1] < 0.005
    assert rates["panning"][1] > 2 * rates["thesis"][1]  # shadowed floor lit at the contact


def test_renders_only_when_the_key_changes(rig):
    gpu, cas, shadows, _ = rig
    s = replace(BASE, cascades=4)
    shadows.sun.render(cas, camera(), 1.0, LIGHT, s, revision=1)
    assert not shadows.sun.render(cas, camera(), 1.0, LIGHT, s, revision=1)
    assert shadows.sun.render(cas, camera(), 1.0, LIGHT, s, revision=2)


def test_stable_fit_does_not_shimmer(rig):
    """Moving and turning the camera a little: with the stable fit the floor's shadow at fixed
    points does not change; the tight fit swims."""
    p, n = floor_points(120, 1.5)
    changed = {}
    for stable in (True, False):
        s = replace(BASE, cascades=4, stable_fit=stable, distance=30.0)
        ref, _ = sun(rig, s, points=(p, n))
        diffs = 0
        for k in range(1, 4):
            cam = camera().set(position=(0.013 * k, 3, 6 - 0.007 * k), yaw=0.4 * k)
            v, _ = sun(rig, s, cam=cam, points=(p, n))
            diffs += int((np.abs(v - ref) > 0.5).sum())
        changed[stable] = diffs
    assert changed[True] == 0
    assert changed[False] > 0


def test_cascades_are_chosen_by_view_depth(rig):
    v, c = sun(rig, replace(BASE, cascades=4, distance=30.0))
    assert set(np.unique(c)) <= {0, 1, 2, 3} and len(np.unique(c)) >= 2
    assert np.all(np.isfinite(v))


def test_hard_two_levels_four_tap_three(rig):
    """Criterion 24: across the shadow's edge hard has exactly two levels, four-tap ≥ 3; PCF,
    PCSS and VSM stay in [0, 1] and agree with hard away from the edge."""
    p, n = floor_points(200, 2.0)
    hard, _ = sun(rig, BASE, points=(p, n))
    assert set(np.unique(np.round(hard, 6))) == {0.0, 1.0}
    four, _ = sun(rig, replace(BASE, filter="four_tap"), points=(p, n))
    assert len(np.unique(np.round(four, 4))) >= 3
    for f in ("pcf", "pcss", "vsm"):
        v, _ = sun(rig, replace(BASE, filter=f), points=(p, n))
        assert v.min() >= 0 and v.max() <= 1 + 1e-6, f
        assert np.abs(v - hard).mean() < 0.05, f


def test_point_light_faces(rig):
    """Criterion 25: the stored (|l| + bias)/range reads about 0.1 one metre below a light of
    range 10 and 1 where nothing is within range; the floor behind the cube is shadowed."""
    gpu, cas, shadows, probe = rig
    pos = np.array([2.0, 1.0, 0.0])
    shadows.point.render(cas, pos, 10.0, replace(BASE, linear_bias=0.0, normal_bias=0.0))
    down = read_face(shadows.point, 3)  # −y
    centre = down[down.shape[0] // 2, down.shape[1] // 2]
    assert centre == pytest.approx(0.1, abs=0.01)
    up = read_face(shadows.point, 2)  # +y: nothing above
    assert np.all(up == 1.0)
    shadows.point.render(cas, pos, 10.0, BASE)
    pts = np.array([[-1.5, 0.0, 0.0], [3.0, 0.0, 1.0]])
    v, _ = probe.visibility(shadows, pts, np.tile([0, 1.0, 0], (2, 1)), light="point")
    assert v[0] == 0.0 and v[1] == 1.0


def test_spot_light_matches_exact(rig):
    gpu, cas, shadows, probe = rig
    pos = np.array([1.5, 3.0, 0.5])
    shadows.spot.render(cas, pos, -pos, 50.0, 20.0, BASE)
    p, n = floor_points(120, 2.0)
    v, _ = probe.visibility(shadows, p, n, light="spot")
    to = (pos - p).reshape(-1, 3)
    truth = ss.occluded(SCENE, p.reshape(-1, 3) + [0, 1e-3, 0], to, max_t=1.0).reshape(v.shape)
    assert ((v < 0.5) != truth).mean() < 0.02
    for bad in ("surfaces.spot_angle=95", "surfaces.spot_range=0", "surfaces.lamp_range=0"):
        with pytest.raises(ParamError, match="out of range"):  # before any map is rendered
            scene_params("surfaces", sets=[bad])


@pytest.mark.parametrize("alpha", [0.25, 0.5, 0.75])
def test_dithered_shadow_fraction(gl_ctx, alpha):
    """Criterion 26: under a large uniform-α occluder the shadowed fraction is α ± 1/16 and the
    pattern repeats every 4 texels of the map."""
    gpu = Gpu(gl_ctx)
    try:
        quad = ss.Quad("pane", (0, 1.0, 0), (3, 0, 0), (0, 0, 3))
        cas = MeshCasters(gpu, "dither", [(ss.mesh(quad), 2, alpha, 0.5, None)])
        shadows, probe = ShadowSet(gpu, "dither"), ShadowProbe(gpu, "dither")
        s = replace(BASE, map_size=256)
        shadows.sun.render(cas, camera(), 1.0, np.array([0.0, 1.0, 0.0]), s)
        texel = 2 * s.fixed_radius / s.map_size
        xs = (np.arange(64) + 0.5) * texel
        x, z = np.meshgrid(xs - 1.0, xs - 1.0)
        p = np.stack([x, np.zeros_like(x), z], -1)
        v, _ = probe.visibility(shadows, p, np.tile([0, 1.0, 0], p.shape[:-1] + (1,)))
        assert (v < 0.5).mean() == pytest.approx(alpha, abs=1 / 16)
        assert np.array_equal(v[:4, :4], v[4:8, 4:8])
    finally:
        gpu.release()


@pytest.mark.parametrize("light", [(0, 1, 0), (1, 1e-4, 0), (0, 1, 1e-9)])
def test_degenerate_lights(rig, light):
    v, _ = sun(rig, replace(BASE, cascades=4), light=np.array(light, float))
    assert np.all(np.isfinite(v)) and v.max() == 1.0


def test_receiver_parallel_to_light_and_zero_cascades(rig):
    wall = np.stack(np.meshgrid(np.linspace(-3, 3, 40), np.linspace(0.1, 2, 40)), -1)
    p = np.stack([wall[..., 0], wall[..., 1], np.full(wall.shape[:-1], -3.5)], -1)
    n = np.tile([0, 0, 1.0], p.shape[:-1] + (1,))
    v, _ = sun(rig, BASE, light=np.array([1.0, 0.0, 0.0]), points=(p, n))
    assert np.all(np.isfinite(v)) and v.max() == 1.0
    cam = camera()
    cam.near = cam.far = 5.0  # every split equal
    v, c = sun(rig, replace(BASE, cascades=4), cam=cam)
    assert np.all(np.isfinite(v)) and v.max() == 1.0


def test_camera_inside_a_casting_box(rig):
    cam = camera().set(position=(0, 0.5, 0))
    v, _ = sun(rig, replace(BASE, cascades=4), cam=cam)
    assert np.all(np.isfinite(v)) and v.max() == 1.0 and v.min() == 0.0


def test_peter_panning_gap_on_a_thin_caster(rig):
    """Criterion 23: linear bias 0.6 detaches the shadow of a 2 cm wall from its foot (a lit gap
    of several texels), the thesis's 0.01 does not."""
    gpu, _, shadows, probe = rig
    wall = ss.Box("wall", (0, 0.5, 0), (0.01, 0.5, 0.5))
    floor = SCENE.boxes[0]
    cas = MeshCasters(gpu, "shadow-test", [(ss.mesh(o), 0, 1.0, 0.5, None) for o in (floor, wall)])
    light = np.array([1.0, 1.0, 0.0]) / np.sqrt(2)
    t = np.linspace(0.0, 0.3, 601)
    p = np.stack([-0.01 - t, np.zeros_like(t), np.zeros_like(t)], -1)
    n = np.tile([0, 1.0, 0], (len(t), 1))
    s = replace(BASE, map_size=1024)
    texel = 2 * s.fixed_radius / s.map_size
    gaps = {}
    for lb in (0.01, 0.6):
        shadows.sun.render(cas, camera(), 1.0, light, replace(s, linear_bias=lb))
        v, _ = probe.visibility(shadows, p, n)
        lit = v >= 0.5
        gaps[lb] = float(t[np.argmin(lit)]) if lit[0] else 0.0
    assert gaps[0.01] == 0.0
    assert gaps[0.6] > 2 * texel
    shadows.sun.key = None  # the rig's own casters next


@pytest.mark.parametrize("taps, radius", [("full", 2), ("fast", 1)])
def test_pcf_reads_the_numpy_gaussian_of_bilinear_compares(rig, taps, radius):
    """The PCF's texel block (ShadowPcfBlock: the (2 r + 2)² texels with separable weights)
    against the numpy twin's sum of (2 r + 1)² bilinear comparisons
    (app.render.shadows.pcf_visibility) on the same map at the same receiver points."""
    from app.render import shadows as rs

    gpu, cas, shadows, probe = rig
    s = replace(BASE, filter="pcf", taps=taps)
    p, n = floor_points(200, 2.0)
    v, _ = sun(rig, s, points=(p, n))
    reach = rs.PCF_RADIUS + 1.0  # ShadowFilterReach of the PCF, in texels along the normal
    moved = p + n * shadows.sun.texel_world[0] * reach
    h = np.concatenate([moved, np.ones(p.shape[:-1] + (1,))], -1) @ shadows.sun.matrices[0].T
    c = h[..., :3] / h[..., 3:]  # the atlas's (u, v, depth): the matrix holds its tile
    truth = rs.pcf_visibility(shadows.sun.read_depth(), c[..., :2], c[..., 2], radius=radius)
    penumbra = (truth > 0.02) & (truth < 0.98)
    assert penumbra.sum() > 500  # the cube's edge crosses the grid
    assert np.abs(v - truth).max() < 2e-3


@pytest.mark.parametrize("filt, mean_bound, max_bound", [("pcf", 0.05, 0.12),
                                                         ("pcss", 0.005, 0.08)])
def test_fast_taps_change_only_the_penumbra_and_little(rig, filt, mean_bound, max_bound):
    """``shadow_taps=fast`` (3 × 3 PCF, PCSS's 4 × 4 blocker search) against the full taps on
    the cube's shadow: where the full filter is fully lit or fully shadowed the fast one agrees
    within 0.011 (PCSS: one of the sun's 32 disc taps, whose radius follows the blocker the
    coarser search finds); across the penumbra it differs by at most ``max_bound`` in
    visibility (the 3 × 3 PCF's penumbra is narrower; measured 0.03 mean and 0.08 max at
    512–2048 texels)."""
    p, n = floor_points(240, 2.5)
    s = replace(BASE, filter=filt, pcss_light_size=0.05)
    full, _ = sun(rig, replace(s, taps="full"), points=(p, n))
    fast, _ = sun(rig, replace(s, taps="fast"), points=(p, n))
    penumbra = (full > 0.01) & (full < 0.99)
    assert penumbra.sum() > 300
    d = np.abs(fast - full)
    assert d[~penumbra].max() <= (1 / 32 + 1e-3 if filt == "pcss" else 0.011)
    assert d[penumbra].mean() < mean_bound and d[penumbra].max() < max_bound
    assert d[penumbra].max() > 0  # the fast taps are in use
