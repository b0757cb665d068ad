"""The procedural-wood thesis's value noise (spec/004 §6 criteria 3–5): GLSL against its numpy
twin.
"""

from __future__ import annotations

import moderngl
import numpy as np
import pytest

from app.sim.noise.value import ValueNoise, random_texture
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
    out = evaluate_points(gpu, pts, PROBE,
                          {"uDepth": depth, "uValueNoiseWrap": (256.0, 256.0, 256.0)}, textures,
                          defines)
    return out[:, :3].astype(np.float64)


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
