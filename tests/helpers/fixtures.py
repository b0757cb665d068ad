"""Fixtures shared by test folders (a domain's GL tests and its stability sweeps use the same
rigs), registered for every test by ``pytest_plugins`` in tests/conftest.py. Each is named by its
domain; a folder- or module-level fixture of the same name would take precedence."""

from __future__ import annotations

import fcntl
import os
from pathlib import Path

import pytest

from app.bakes import CACHE_ENV
from app.effects.preetham import Preetham
from app.gpu.device import Gpu
from app.params import ParamSet
from app.sim import atmosphere as atm
from tests.helpers import clouds, clouds_b, hillaire, ocean, preetham
from tests.helpers.noise_probe import NoiseProbe

#: the scenes whose first frame samples the cloud noise that ``bake_cloud_noise`` bakes
BAKING_SCENES = ("clouds", "noise", "ocean", "maritime")


def bake_cloud_noise(gl_ctx) -> None:
    """The cloud noise of the default scenes (``app.bakes.defaults()`` and ``maritime()``) in
    the run's cache: the first test process to get here bakes it while the others wait on a
    lock, then load it. (Two processes that started on an empty cache side by side both baked
    it: ~4.4 s of CPU each.)"""
    from app.bakes import bake, defaults, maritime

    with open(Path(os.environ[CACHE_ENV]) / "cloud-noise.lock", "a") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # released when the file is closed
        gpu = Gpu(gl_ctx)
        try:
            for spec in defaults() + maritime():
                bake(gpu, spec)
        finally:
            gpu.release()


@pytest.fixture(scope="module")
def atmosphere_model() -> atm.AtmosphereParams:
    return atm.AtmosphereParams()


@pytest.fixture(scope="module")
def atmosphere_lut(atmosphere_model) -> atm.OpticalDepthLut:
    return atm.OpticalDepthLut(atmosphere_model)


@pytest.fixture(scope="module")
def noise_probe(gl_ctx):
    """GLSL noise expressions evaluated at points (compute shaders)."""
    gpu = Gpu(gl_ctx)
    if not gpu.caps.compute:
        pytest.skip(f"the noise probe needs compute shaders; {gpu.caps.describe()}")
    p = NoiseProbe(gpu, owner="noise-test")
    yield p
    p.release()
    gpu.release()


@pytest.fixture
def clouds_rig(gl_ctx):
    """Cloud model A scenes with a fixed light: ``clouds_rig(sets, camera, scene)``."""
    rigs = []

    def make(sets=(), camera=None, scene="clouds"):
        r = clouds.Rig(gl_ctx, list(clouds.FIXED_LIGHT) + list(sets), camera, scene)
        rigs.append(r)
        return r

    yield make
    for r in rigs:
        r.release()


@pytest.fixture(scope="module")
def clouds_b_rig(gl_ctx):
    """Cloud model B on its own, its bakes in the test run's cache (``session_cache``)."""
    gpu = Gpu(gl_ctx)
    r = clouds_b.Rig(gpu)
    r.reset()
    yield r
    gpu.release()


@pytest.fixture(scope="module")
def preetham_rig(gl_ctx):
    """(gpu, params, effect, target) of the Preetham sky on its own."""
    gpu = Gpu(gl_ctx)
    params = ParamSet(Preetham.declare(gpu.shaders))
    fx = Preetham(gpu, params)
    target = gpu.target("test", "preetham", preetham.SIZE)
    yield gpu, params, fx, target
    gpu.release()


@pytest.fixture(scope="module")
def hillaire_rig(gl_ctx):
    r = hillaire.Rig(gl_ctx)
    yield r
    r.release()


@pytest.fixture
def ocean_shot(gl_ctx):
    """Ocean sessions that keep their target: ``ocean_shot(sets, camera, size)``."""
    made = []

    def _make(sets=(), camera=None, size=(96, 54)):
        s = ocean.Shot(gl_ctx, sets, camera, size)
        made.append(s)
        return s

    yield _make
    for s in made:
        s.close()
