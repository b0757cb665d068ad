"""The procedural-wood thesis's value noise (spec/004 §6 criteria 2–9): GLSL against its numpy twin,
and the twin against the properties the digest derives."""

from __future__ import annotations

import moderngl
import numpy as np
import pytest

from app.sim.noise.value import ValueNoise, ease_in, ease_in_out, random_texture
from tests.helpers.glsl_eval import evaluate_points

PROBE = "tests/value_noise_probe"


@pytest.fixture
def noise_gpu(gpu):
    """(gpu, bound texture pair, numpy twin) for seed 1."""
    tex = gpu.texture("test", "value noise", (256, 256), 4, random_texture(1).tobytes(), dtype="f1",
                      filter=(moderngl.NEAREST, moderngl.NEAREST), repeat=True)
    return gpu, [("uValueNoiseTex", tex)], ValueNoise(1)


def gpu_eval(noise_gpu, pts, depth=0, pixel=False):
    gpu, textures, _ = noise_gpu
    defines = {"PROBE_PIXEL": 1} if pixel else {}
    out = evaluate_points(gpu, pts, PROBE, {"uDepth": depth, "uValueNoiseWrap": (256.0, 256.0, 256.0)}, textures, defines)
    return out[:, :3].astype(np.float64)


def test_ease_curves():  # criterion 2
    assert ease_in_out(0.0) == 0 and ease_in_out(1.0) == 1 and ease_in_out(0.5) == pytest.approx(0.5)
    assert ease_in_out(-3.0) == 0 and ease_in_out(7.0) == 1
    h = 1e-6
    assert abs(ease_in_out(h) - ease_in_out(0.0)) / h < 1e-4
    assert abs(ease_in_out(1.0) - ease_in_out(1.0 - h)) / h < 1e-4
    t = np.linspace(0, 1, 11)
    assert np.allclose(ease_in(t), t * t)


def test_hash_gpu_equals_cpu_exactly_on_a_lattice(noise_gpu):  # criterion 3
    g = np.arange(0, 256, 8, dtype=np.float64)
    pts = np.stack(np.meshgrid(g, g, g, indexing="ij"), -1).reshape(-1, 3)  # 32³
    got = gpu_eval(noise_gpu, pts, pixel=True)
    want = noise_gpu[2].get_pixel(pts)
    assert np.abs(got - want).max() <= 1e-6


def test_noise_at_lattice_points_is_the_hashed_value(noise_gpu):  # criterion 4
    rng = np.random.default_rng(4)
    pts = rng.integers(-300, 300, size=(2000, 3)).astype(np.float64)
    twin = noise_gpu[2]
    lattice = np.mod(pts, 256.0)
    assert np.abs(twin.noise3(pts) - twin.get_pixel(lattice)).max() <= 1e-5
    assert np.abs(gpu_eval(noise_gpu, pts) - twin.get_pixel(lattice)).max() <= 1e-5


def test_gpu_matches_twin_at_random_points(noise_gpu):
    rng = np.random.default_rng(5)
    pts = rng.uniform(-50, 50, size=(20000, 3))
    twin = noise_gpu[2]
    for depth in (0, 1, 3, 8):
        got = gpu_eval(noise_gpu, pts, depth)
        want = twin.noise3(pts) if depth == 0 else twin.octaves(pts, depth)
        assert np.abs(got - want).max() < 2e-4, depth


def test_range(noise_gpu):  # criterion 5: 10⁵ points on the GPU, a sample of them on the CPU
    rng = np.random.default_rng(6)
    pts = rng.uniform(-1000, 1000, size=(100000, 3))
    twin = noise_gpu[2]
    for depth in range(0, 9):
        g = gpu_eval(noise_gpu, pts, depth)
        assert g.min() >= 0.0 and g.max() <= 1.0, depth
    for depth in (1, 8):
        v = twin.octaves(pts[:10000], depth)
        assert v.min() >= 0.0 and v.max() <= 1.0


def test_periodic_in_256_and_no_seam_at_zero():  # criterion 6
    twin = ValueNoise(1)
    rng = np.random.default_rng(7)
    pts = rng.uniform(-40, 40, size=(5000, 3))
    for k in range(3):
        shifted = pts.copy()
        shifted[:, k] += 256.0
        assert np.abs(twin.noise3(shifted) - twin.noise3(pts)).max() <= 1e-4
    eps = 1e-5
    for k in range(3):
        a = np.zeros((200, 3)) + rng.uniform(-5, 5, (200, 3))
        a[:, k] = -eps
        b = a.copy()
        b[:, k] = eps
        assert np.abs(twin.noise3(a) - twin.noise3(b)).max() < 1e-3


def test_c1_continuity_across_cell_faces():  # criterion 7
    twin = ValueNoise(1)
    rng = np.random.default_rng(8)
    eps = 1e-4
    for k in range(3):
        pts = rng.uniform(0, 30, size=(2000, 3))
        pts[:, k] = np.floor(pts[:, k])  # on a lattice plane
        lo, hi = pts.copy(), pts.copy()
        lo[:, k] -= eps
        hi[:, k] += eps
        assert np.abs(twin.noise3(hi) - twin.noise3(lo)).max() < 1e-3
        slope = (twin.noise3(hi) - twin.noise3(lo)) / (2 * eps)
        assert np.abs(slope).max() < 1e-2  # the fade's derivative vanishes on the faces


def test_octave_formula():  # criterion 8
    twin = ValueNoise(2)
    rng = np.random.default_rng(9)
    p = rng.uniform(-20, 20, size=(3000, 3))
    assert np.allclose(twin.octaves(p, 1), twin.noise3(p), atol=1e-12)
    for d in (2, 3, 5, 8):
        explicit = sum(2.0**-i * twin.noise3(2.0**i * p) for i in range(d)) / sum(2.0**-i for i in range(d))
        assert np.abs(twin.octaves(p, d) - explicit).max() <= 1e-5
    assert np.allclose(twin.octaves(p, 0), twin.octaves(p, 1)) and np.allclose(twin.octaves(p, 12), twin.octaves(p, 8))


def test_statistics_per_depth():  # criterion 9
    twin = ValueNoise(1)
    rng = np.random.default_rng(10)
    p = rng.uniform(-50, 50, size=(6000, 3))
    expected = {1: 0.185, 3: 0.121, 8: 0.107}
    tol = {1: 0.02, 3: 0.015, 8: 0.015}
    stds = []
    for d in range(1, 9):
        v = twin.octaves(p, d)
        stds.append(v.std(axis=0).mean())
        assert np.all(np.abs(v.mean(axis=0) - 0.5) < 0.02)
        if d in expected:
            assert np.all(np.abs(v.std(axis=0) - expected[d]) < tol[d]), (d, v.std(axis=0))
        c = np.corrcoef(v.T)
        assert np.abs(c[np.triu_indices(3, 1)]).max() < 0.1
    assert all(b <= a + 2e-3 for a, b in zip(stds, stds[1:]))
    raw = twin.table.reshape(-1, 3)
    assert abs(raw.std() - 0.289) < 0.005
