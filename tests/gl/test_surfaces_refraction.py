"""Refraction and Fresnel on the GPU (spec/003 §2.7; criterion 20's GPU twin, the refraction
half of criterion 21): glsl/common/fresnel.glsl and glsl/surfaces/refraction.glsl evaluated by
glsl/surfaces/refraction_eval.frag against the numpy twin app/sim/optics.py, and a sphere
refracting a cubemap made by code (128² pixels)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from app.gpu.device import Gpu
from app.sim import optics as op
from app.sim.sky import cubemap_face_direction
from tests.helpers.glsl_eval import evaluate_points

EVAL = "surfaces/refraction_eval"
CUBE = 64
EYE = np.array([0.0, 0.0, 3.0])
FOV = math.radians(60.0)
SPHERE = {"uSphereCentre": (0.0, 0.0, 0.0), "uSphereRadius": 1.0}
Z = np.array([0.0, 0.0, 1.0])


def env_colour(d):
    """The code-made background: smooth, different along every axis."""
    return 0.5 + 0.5 * np.stack([np.sin(3.0 * d[..., 0] + 0.5), np.sin(2.5 * d[..., 1] + 1.0),
                                 np.cos(2.0 * d[..., 2] + 0.3 * d[..., 0])], axis=-1)


class Rig:
    def __init__(self, gl_ctx):
        self.gpu = Gpu(gl_ctx)
        self.cube = self.gpu.texture_cube("test-refraction", "env", CUBE, 4, dtype="f4")
        c = (np.arange(CUBE) + 0.5) / CUBE * 2.0 - 1.0
        s, t = np.meshgrid(c, c)
        for face in range(6):
            d = cubemap_face_direction(face, s, t)
            rgba = np.concatenate([env_colour(d), np.ones(s.shape + (1,))], axis=-1)
            self.cube.write(face, rgba.astype(np.float32).tobytes())
        import moderngl
        self.cube.filter = (moderngl.LINEAR, moderngl.LINEAR)

    def eval(self, points, mode, **uniforms):
        u = {"uEvalMode": mode, "uNormal": (0.0, 0.0, 1.0), "uTangent": (1.0, 0.0, 0.0),
             "uBitangent": (0.0, 1.0, 0.0), "uEta": 1.0, "uEye": tuple(EYE), "uInterfaces": 1,
             "uFov": FOV, **SPHERE}
        u.update(uniforms)
        return evaluate_points(self.gpu, points, EVAL, u, textures=[("uEnv", self.cube)])

    def image(self, n2, interfaces=1, n1=1.0, size=128):
        c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
        x, y = np.meshgrid(c, c)
        pts = np.stack([x, y, np.zeros_like(x)], axis=-1).reshape(-1, 3)
        out = self.eval(pts, 4, uEta=n1 / n2, uInterfaces=interfaces)
        return out.reshape(size, size, 4)


@pytest.fixture(scope="module")
def rig(gl_ctx):
    r = Rig(gl_ctx)
    yield r
    r.gpu.release()


def test_fresnel_functions_match_the_numpy_twin(rig):
    cos = np.linspace(0.0, 1.0, 41)
    idx = np.array([1.0, 1.15, 1.31, 1.52, 2.42])
    c, a, b = np.meshgrid(cos, idx, idx, indexing="ij")
    pts = np.stack([c, a, b], axis=-1).reshape(-1, 3).astype(np.float32).astype(np.float64)
    out = rig.eval(pts, 0)
    assert np.abs(out[:, 0] - op.fresnel_exact(pts[:, 0], pts[:, 1], pts[:, 2])).max() < 1e-5
    assert np.abs(out[:, 1] - op.fresnel_schlick(pts[:, 0], pts[:, 1], pts[:, 2])).max() < 1e-5
    # SchlickFresnel(f0 = p.y, cos θ = p.x): f0 here the index, only as a number
    assert np.abs(out[:, 2] - op.schlick_fresnel(pts[:, 1], pts[:, 0])).max() < 1e-5
    assert np.all(np.isfinite(out))


@pytest.mark.parametrize("eta", [1.0, 1 / 1.31, 1 / 2.42, 1.31, 1.52])
def test_refract_direction_matches_the_numpy_twin(rig, eta):
    rng = np.random.default_rng(1)
    v = rng.normal(size=(2000, 3))
    v[:, 2] = -np.abs(v[:, 2])                         # toward the surface of normal +z
    v = (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(np.float32).astype(np.float64)
    k = 1.0 - eta * eta * (1.0 - v[:, 2] ** 2)
    keep = np.abs(k) > 1e-3                            # off the critical angle's square root
    out = rig.eval(v, 1, uEta=eta)
    r, tir = op.refract_direction(v, Z, eta)
    assert np.array_equal(out[keep, 3] > 0.5, tir[keep])
    assert np.abs(out[keep, :3] - r[keep]).max() < 1e-5
    assert np.all(np.isfinite(out))


@pytest.mark.parametrize("interfaces", [1, 2])
def test_refract_through_sphere_matches_the_numpy_twin(rig, interfaces):
    rng = np.random.default_rng(2)
    p = rng.normal(size=(1500, 3))
    p[:, 2] = np.abs(p[:, 2]) + 0.3                    # the half facing the eye
    p /= np.linalg.norm(p, axis=1, keepdims=True)
    p = p[p[:, 2] > 0.4]                               # seen from the eye (p·(eye − p) > 0)
    p = p.astype(np.float32).astype(np.float64)
    for eta in (1 / 1.31, 1 / 2.42):
        out = rig.eval(p, 2, uEta=eta, uInterfaces=interfaces)
        d, tir = op.refract_sphere(interfaces, p, p - EYE, SPHERE["uSphereCentre"], 1.0, eta)
        assert not tir.any() and not (out[:, 3] > 0.5).any()
        # two chained float32 refractions near grazing: 1.2e-5 seen on llvmpipe
        assert np.abs(out[:, :3] - d).max() < (1e-5 if interfaces == 1 else 5e-5)


def test_distortion_and_lod_match_the_numpy_twin(rig):
    rng = np.random.default_rng(3)
    pts = np.column_stack([rng.uniform(-1, 1, 500), rng.uniform(-1, 1, 500) * 8.0,
                           rng.uniform(0, 2, 500)]).astype(np.float32).astype(np.float64)
    out = rig.eval(pts, 3)
    n = op.distort_normal(Z, [1.0, 0, 0], [0, 1.0, 0], pts[:, :2], pts[:, 2])
    assert np.abs(out[:, :3] - n).max() < 1e-5
    assert np.abs(out[:, 3] - op.refraction_lod(pts[:, 0], pts[:, 1])).max() < 1e-5


def test_criterion_21_equal_indices_show_the_background_undistorted(rig):
    direct = rig.image(1.0, n1=1.0, size=128)
    size = 128
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    x, y = np.meshgrid(c, c)
    f = math.tan(0.5 * FOV)
    v = np.stack([x * f, y * f, -np.ones_like(x)], axis=-1)
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    truth = env_colour(v)                             # the direct lookup, in numpy
    for interfaces in (1, 2):
        img = rig.image(1.31, n1=1.31, interfaces=interfaces)
        assert np.abs(img[..., :3] - direct[..., :3]).mean() < 2.0 / 255.0
    assert np.abs(direct[..., :3] - truth).mean() < 2.0 / 255.0


@pytest.mark.parametrize("interfaces", [1, 2])
def test_criterion_21_larger_n2_deviates_more(rig, interfaces):
    direct = rig.image(1.0)[..., :3]
    dev = [float(np.abs(rig.image(n2, interfaces=interfaces)[..., :3] - direct).mean())
           for n2 in (1.0, 1.15, 1.31, 2.42)]
    assert dev[0] < 1e-6
    assert all(b > a + 1e-3 for a, b in zip(dev, dev[1:])), dev


def test_total_internal_reflection_region_has_no_nan(rig):
    # a bubble: the sphere's index (1) below the medium's (1.31): grazing rays totally reflect
    for interfaces in (1, 2):
        img = rig.image(1.0, n1=1.31, interfaces=interfaces)
        assert np.all(np.isfinite(img))
        tir = img[..., 3] > 0.5
        assert 0 < tir.sum() < tir.size
