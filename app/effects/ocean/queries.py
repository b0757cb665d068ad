"""Water-height queries: what floating objects and the camera ask the ocean (the frame's
``water`` slot, an :class:`app.frame.WaterSurface`).

Sine and Gerstner are evaluated exactly in numpy; the FFT reads back the displacement textures
(each cascade on the grid the view chose; bilinear as the surface's texture lookups)
asynchronously — the answer describes the sea **one frame earlier** (the frame before the last
``update``), never stalls the GPU, and its time is ``query_time`` — except on the first frame
of a sea, which reads its own simulation at once (one stall) so nothing starts on flat water.
Heights come from the iterative inversion of the horizontal displacement (spec/000 §1.3, 3
corrections + a final read); normals from central differences with a step inside the shortest wave.
"""

from __future__ import annotations

import numpy as np

from ...sim import ocean as oc
from ...sim.vec import cross
from .params import wind_vector


class WaterQueries:
    """The frame's ``water`` slot (:class:`app.frame.WaterSurface`) over the :class:`~.sea.Sea`
    ``sea``, as of the last frame (``time``, ``camera_pos``) and the last FFT readback."""

    def __init__(self, params, sea):
        self.params, self.sea = params, sea
        self.time = 0.0
        self.camera_pos = np.zeros(3)
        self.query_time: float | None = None
        self._readback = None
        self._readback_groups: list = []  # the readback grouped by grid size

    def forget(self) -> None:
        """A new FFT sea: flat water until it is read back."""
        self._readback = None
        self.query_time = None

    def take(self, got) -> None:
        """The FFT's newest readback (time, fields), or None: the sea the answers describe."""
        if got is not None and got is not self._readback:
            self._readback = got
            self._readback_groups = oc.group_cascade_grids(got[1], self.sea.patch_sizes())
            self.query_time = got[0]

    def fade_range(self) -> tuple[float, float]:
        """Distances from the camera [m] over which the displacement fades to flat water (the
        shaders' uFadeStart/uFadeEnd and the queries alike)."""
        extent = self.params["ocean.mesh_extent"]
        return 0.5 * extent, 0.9 * extent

    def _fade(self, x, z):
        """The fade factor at (x, z), or None where every point lies inside the fade's start
        (the factor is exactly 1 there: the multiplication is skipped, the result the same)."""
        start, end = self.fade_range()
        r = np.hypot(np.asarray(x) - self.camera_pos[0], np.asarray(z) - self.camera_pos[2])
        if r.size and r.max() <= start:  # (NaN compares false: the full formula)
            return None
        # np.clip(·, 0, 1) as the two ufuncs it is (its argument handling costs more; the
        # buoyancy asks for ~3000 fades a spin-up)
        t = np.minimum(np.maximum((r - start) / (end - start), 0.0), 1.0)
        return 1.0 - t * t * (3.0 - 2.0 * t)

    def displacement(self, x, z) -> np.ndarray:
        """(D_x, η, D_z) [m] of the rest points (x, z) as drawn (faded far from the camera)."""
        x = np.asarray(x, dtype=float)
        z = np.asarray(z, dtype=float)
        model = self.params["ocean.model"]
        if model == "sine":
            a, k, w = self.sea.sine_wave()
            d = wind_vector(self.sea.wind_direction())
            eta = a * np.sin(k * (d[0] * x + d[1] * z) - w * self.time)
            out = np.stack([np.zeros_like(eta), eta, np.zeros_like(eta)], axis=-1)
        elif model == "gerstner":
            surf = oc.gerstner(x, z, self.time, self.sea.gerstner_waves(),
                               depth=self.params["ocean.depth"])
            out = surf.position - np.stack([x, np.zeros_like(x), z], axis=-1)
        else:
            if self._readback is None:
                out = np.zeros(x.shape + (3,))
            else:
                # (λD_x, η, λD_z) alone: the Jacobian channel is not interpolated
                out = oc.sample_cascade_groups(self._readback_groups, x, z, channels=3)
                if out.shape != x.shape + (3,):
                    out = np.broadcast_to(out, x.shape + (3,)).copy()
        fade = self._fade(x, z)
        return out if fade is None else out * fade[..., None]

    def height(self, x, z) -> np.ndarray:
        """Water height [m] above world points (x, z): :meth:`water` without the normal."""
        return oc.invert_horizontal_displacement(self.displacement, x, z,
                                                 self.params["ocean.query_iterations"],
                                                 residuals=False)[2][..., 1]

    def normal(self, x, z) -> np.ndarray:
        """Unit normal of the water above world points (x, z): :meth:`water`'s normal."""
        return self.water(x, z).normal

    def water(self, x, z, iterations: int | None = None) -> oc.WaterQuery:
        """Height, displacement and unit normal of the water above world points (x, z).

        Sine and Gerstner: exact at the current time. FFT: from the last completed readback (one
        frame old, see the module docstring); flat water before the first one."""
        if iterations is None:
            iterations = self.params["ocean.query_iterations"]
        x0, z0, d, res = oc.invert_horizontal_displacement(self.displacement, x, z, iterations)
        # normal of the displaced surface by central differences around the rest point, with a
        # step well inside the shortest wave (or the finest FFT texel)
        e = self._difference_step()
        px1, px0 = self.displacement(x0 + e, z0), self.displacement(x0 - e, z0)
        pz1, pz0 = self.displacement(x0, z0 + e), self.displacement(x0, z0 - e)
        t = np.stack([2 * e + px1[..., 0] - px0[..., 0], px1[..., 1] - px0[..., 1],
                      px1[..., 2] - px0[..., 2]], -1)
        b = np.stack([pz1[..., 0] - pz0[..., 0], pz1[..., 1] - pz0[..., 1],
                      2 * e + pz1[..., 2] - pz0[..., 2]], -1)
        n = cross(b, t)
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
        return oc.WaterQuery(d[..., 1], d, n, x0, z0, res)

    def _difference_step(self) -> float:
        model = self.params["ocean.model"]
        if model == "sine":
            return min(0.05, self.params["ocean.sine_wavelength"] / 50.0)
        if model == "gerstner":
            return min(0.05, min(w.wavelength for w in self.sea.gerstner_waves()) / 50.0)
        sea = self.sea
        sizes = sea.sim.sizes if sea.sim is not None else [int(self.params["ocean.fft_size"])]
        return min(0.05, 0.5 * min(size / n for size, n in zip(sea.patch_sizes(), sizes)))
