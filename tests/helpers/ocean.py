"""Shared by the ocean tests in tests/gl and tests/stability: an ocean session that keeps its
target (colour and depth), and the GPU FFT simulation against the numpy reference
app/sim/ocean.py (tolerances: tests/gl/test_ocean_gpu.py).
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from app.effects.ocean import Ocean
from app.effects.ocean.fft import GpuOceanSim
from app.runtime import open_session, scene_params
from app.sim import ocean as oc
from app.sim.camera import Camera

FAST = ("ocean.fft_size=64", "ocean.mesh_segments=96", "scene.clouds=off")


class Shot:
    """An ocean session that keeps its target, so tests can read colour and depth."""

    def __init__(self, ctx, sets=(), camera: Camera | None = None, size=(96, 54)):
        params = scene_params("ocean", sets=list(FAST) + list(sets))
        self.session = open_session("ocean", params, ctx=ctx, camera=camera)
        self.scene = self.session.scene
        self.ocean: Ocean = self.scene.effect("ocean")
        self.size = size
        self.target = self.session.gpu.target("test", "ocean shot", size)

    def frame(self, dt: float = 0.0):
        f = self.scene.frame(self.size, dt=dt)
        self.scene.render(f, self.target)
        return self.target.read()[..., :3], f

    def distance(self) -> np.ndarray:
        """Distance from the camera to what each pixel shows (inf where nothing was drawn)."""
        cam = self.scene.camera
        depth = self.target.read_depth()
        w, h = self.size
        ndc_z = depth * 2.0 - 1.0
        n, f = cam.near, cam.far
        z_eye = 2.0 * n * f / (f + n - ndc_z * (f - n))
        dirs = cam.ray_directions(w, h)
        cos = dirs @ cam.basis()[2]
        dist = z_eye / cos
        return np.where(depth >= 1.0, np.inf, dist)

    def close(self):
        if self.session is not None:
            self.session.release()
            self.session = None


FIELD_TOL = 1e-5


FIELDS = ("height", "disp_x", "disp_z", "slope_x", "slope_z", "ddx_dx", "ddz_dz", "ddx_dz",
          "jacobian")

PATHS = [pytest.param(True, id="compute"), pytest.param(False, id="fragment")]


@functools.lru_cache(maxsize=None)
def reference(n: int, sizes: tuple, wind: float = 12.0, seed: int = 3) -> oc.FFTOcean:
    return oc.FFTOcean(oc.SpectrumParams(kind="jonswap", wind_speed=wind), n=n, patch_sizes=sizes,
                       choppiness=1.0, seed=seed)


def fields_at(ocean: oc.FFTOcean, t: float, lam: float = 1.0):
    return [oc.synthesize(oc.evolve_amplitudes(c.h0, c.omega, t), c.kx, c.kz, lam)
            for c in ocean.cascades]


def relative_error(got: np.ndarray, ref: np.ndarray, key: str) -> float:
    scale = np.max(np.abs(ref - 1.0)) if key == "jacobian" else np.max(np.abs(ref))
    return (float(np.max(np.abs(got - ref)) / scale) if scale > 0
            else float(np.max(np.abs(got - ref))))


def worst_errors(sim: GpuOceanSim, refs) -> dict[str, float]:
    worst: dict[str, float] = {}
    for i, ref in enumerate(refs):
        got = sim.read_fields(i)
        for key in FIELDS:
            worst[key] = max(worst.get(key, 0.0), relative_error(got[key], getattr(ref, key), key))
    return worst


def make_sim(gpu, ocean: oc.FFTOcean, use_compute: bool) -> GpuOceanSim:
    sim = GpuOceanSim(gpu, "ocean-test", use_compute=use_compute)
    sim.set_spectrum(ocean.cascades, ocean.n)
    return sim
