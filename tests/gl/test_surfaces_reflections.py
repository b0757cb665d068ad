"""The reflection probe on the GPU (spec/003 §2.5, §2.6): glsl/surfaces/reflection.glsl against
its numpy twin (criterion 21's CPU/GPU check), a mirror floor with box projection against the
exact ray cast, the blur of rough reflections, and the capture's caching."""

from __future__ import annotations

import numpy as np
import pytest

from app.effects.surfaces.reflections import PROBE_EVAL, PositionScene, ReflectionProbe
from app.gpu.device import Gpu
from app.sim import reflections as rf
from app.sim import surfaces_scene as ss
from tests.helpers.glsl_eval import evaluate_points

SCENE = ss.default_scene()
ROOM = SCENE.room
EYE = np.array([0.0, 1.6, 3.5])


class Rig:
    def __init__(self, gl_ctx, params=None):
        self.gpu = Gpu(gl_ctx)
        self.scene = PositionScene(self.gpu, "test-reflections", ss.SurfacesScene(room=ROOM))
        self.probe = ReflectionProbe(self.gpu, "test-reflections", params)

    def update(self, key=1):
        return self.probe.update(key, self.scene.draw, SCENE.probe_position, ROOM.lo, ROOM.hi)

    def eval(self, points, **uniforms):
        u = dict(self.probe.uniforms())
        u.update(uniforms)
        return evaluate_points(self.gpu, points, PROBE_EVAL, u,
                               textures=list(self.probe.textures().items()))


@pytest.fixture(scope="module")
def rig(gl_ctx):
    r = Rig(gl_ctx, {"surfaces.probe_size": 64, "surfaces.prefilter_samples": 32})
    r.update()
    yield r
    r.probe.release()
    r.gpu.release()


def _floor(n=400, seed=0):
    rng = np.random.default_rng(seed)
    return np.stack([rng.uniform(-3.6, 3.6, n), np.zeros(n), rng.uniform(-3.6, 3.6, n)], 1)


def _reflected(points):
    d = points - EYE
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return d * [1.0, -1.0, 1.0]


@pytest.mark.parametrize("mode", rf.MODES)
def test_compute_reflex_direction_matches_the_numpy_twin(rig, mode):
    p = _floor()
    p[:, 1] = np.random.default_rng(2).uniform(0.0, 2.9, len(p))  # anywhere in the room
    r = _reflected(p)
    pr = rig.probe
    out = rig.eval(p, uEvalMode=0, uReflection=rf.MODE_CODE[mode], uPerPointDir=1,
                   uEye=tuple(EYE), uNormal=(0.0, 1.0, 0.0), uSphereNormal=0)
    want = rf.compute_reflex_direction(mode, p, r, pr.position, pr.box_min, pr.box_max,
                                       pr.sphere_radius)
    assert np.allclose(out[:, :3], want, atol=2e-4 * max(1.0, np.abs(want).max()))
    # criterion 21: the perfect sphere's t ∈ [0, 1] and |P(t) − C| = r, on the GPU too
    t = out[:, 3]
    assert np.all((t >= 0) & (t <= 1))
    if mode == "perfect":
        assert np.allclose(np.linalg.norm(out[:, :3], axis=1), pr.sphere_radius, atol=1e-4)


def test_weight_lut_and_specular_colour_match_the_twin(rig):
    s, m, nh = np.meshgrid(np.linspace(0, 1, 5), np.linspace(0, 1, 5), np.linspace(0.5, 1, 8))
    p = np.stack([s.ravel(), m.ravel(), nh.ravel()], 1)
    albedo, light = (0.9, 0.6, 0.2), (1.0, 0.95, 0.9)
    out = rig.eval(p, uEvalMode=1, uAlbedo=albedo, uLight=light)
    table = {(0, 0): 0.0, (0, 1): 0.75, (1, 0): 0.25, (1, 1): 1.0}  # criterion 19 on the GPU
    for (sv, mv), w in table.items():
        sel = (p[:, 0] == sv) & (p[:, 1] == mv)
        assert np.all(out[sel, 0] == w)
    lut = rf.nhx_roughness_lut(64)
    want = rf.specular_intensity_from_lut(lut, p[:, 2], 1.0 - p[:, 0])
    assert np.allclose(out[:, 1], want, atol=2e-3 * 16)
    colour = rf.specular_color_by_metallic(light, albedo, p[:, 1])
    assert np.allclose(out[:, 2:4], colour[:, :2], atol=1e-6)


def test_mirror_floor_with_box_projection_shows_the_walls_the_ray_cast_hits(rig):
    p = _floor()
    r = _reflected(p)
    t, index = ss.ray_cast(ss.SurfacesScene(room=ROOM), p + 1e-4 * r, r)
    hit = p + 1e-4 * r + t[:, None] * r
    assert np.all(index == -1)
    err = {}
    for mode in ("cube", "box"):
        seen = rig.eval(p, uEvalMode=2, uReflection=rf.MODE_CODE[mode], uEye=tuple(EYE),
                        uNormal=(0.0, 1.0, 0.0), uSphereNormal=0, uSmoothness=1.0)[:, :3]
        err[mode] = np.linalg.norm(seen - hit, axis=1)
    # the probe's colour is the world position it saw: box projection finds the ray cast's
    # wall point (to the capture's texel size); the plain cube lookup sees the wall the probe
    # centre would, metres away
    assert np.median(err["box"]) < 0.02 and np.percentile(err["box"], 95) < 0.1
    assert np.median(err["cube"]) > 1.0


def test_rough_reflections_blur_monotonically(rig):
    rng = np.random.default_rng(5)
    d = rng.normal(size=(1500, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    for mode in (3, 4):  # SampleProbe over the mips, PrefilteredSpecular over GGX levels
        spread = []
        for smooth in (1.0, 0.75, 0.5, 0.25, 0.0):
            out = rig.eval(d, uEvalMode=mode, uSmoothness=smooth)[:, :3]
            assert np.all(np.isfinite(out))
            spread.append(float(out.var(axis=0).sum()))
        assert all(a > b for a, b in zip(spread, spread[1:])), (mode, spread)
        assert spread[-1] < 0.6 * spread[0]


def test_the_split_sum_lut_matches_its_numpy_twin(rig):
    lut = np.frombuffer(rig.probe.brdf.read(), np.float32).reshape(64, 64, 2)
    t = (np.arange(4, 64, 8) + 0.5) / 64  # texel centres of every 8th texel
    want = rf.brdf_ab(t[None, :], t[:, None], 256)
    got = lut[4::8, 4::8]
    assert np.allclose(got, want, atol=2e-4)


def test_the_probe_captures_only_when_its_key_changes(gl_ctx):
    r = Rig(gl_ctx, {"surfaces.probe_size": 64, "surfaces.prefilter_samples": 8})
    try:
        assert r.update(key="a") is True
        assert (r.probe.captures, r.probe.prefilters) == (1, 1)
        assert r.update(key="a") is False
        assert r.update(key="a") is False
        assert (r.probe.captures, r.probe.prefilters) == (1, 1)
        assert r.update(key="b") is True
        assert (r.probe.captures, r.probe.prefilters) == (2, 2)
        assert r.probe.capture_ms > 0 and r.probe.mips == 7
        owned = {a.name for a in r.gpu.owned_by("test-reflections")}
        assert {"reflection probe", "prefiltered probe", "BRDF LUT",
                "NHxRoughness LUT"} <= owned
        with pytest.raises(ValueError, match="allowed"):
            r.probe.update("c", r.scene.draw, (0, 1, 0), (1, 0, 0), (0, 3, 1))
    finally:
        r.probe.release()
        r.gpu.release()
