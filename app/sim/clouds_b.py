"""Numpy twins of Cloud Model B's shader functions (glsl/clouds_b/clouds_b_model.glsl;
spec/000 §1.6 and its annex A code listings). Names follow the GLSL ``CloudsB…`` functions in
snake case.

The noise lookups are passed in as callables (``volume(p) → (…, 4)``, ``detail(p) → (…, 3)``,
``coverage(p) → (…)``), so a test can evaluate the exact density and light march the shader
computes with constant or analytic noise.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .optics import henyey_greenstein, ray_box


def ray_box_distance(bounds_min, bounds_max, origin, direction) -> np.ndarray:
    """spec/000 §A.4: (dstToBox, dstInsideBox), last axis; ``direction`` is passed as is (the
    fix: not 1/L) and zero components are allowed (replaced by ±1e-20 like the shader)."""
    dst_a, dst_b = ray_box(origin, direction, bounds_min, bounds_max)
    to_box = np.maximum(0.0, dst_a)
    inside = np.maximum(0.0, dst_b - to_box)
    return np.stack([to_box, inside], axis=-1)


def phase(cos_alpha, forward: float, back: float, base_brightness: float,
          phase_factor: float) -> np.ndarray:
    """spec/000 §A.3: P.z + P.w·(0.5·HG(cos α, P.x) + 0.5·HG(cos α, −P.y)), HG the
    Henyey–Greenstein phase of spec/000 eq. 3.1."""
    hg = 0.5 * henyey_greenstein(cos_alpha, forward) + 0.5 * henyey_greenstein(cos_alpha, -back)
    return base_brightness + phase_factor * hg


def beer(d) -> np.ndarray:
    """spec/000 eq. 3.2: Beer(d) = e^{−d}."""
    return np.exp(-np.asarray(d, dtype=np.float64))


def powder(d) -> np.ndarray:
    """spec/000 eq. 3.3: Powder(d) = 1 − e^{−2d}."""
    return 1.0 - np.exp(-2.0 * np.asarray(d, dtype=np.float64))


def remap(v, a, b, c, d):
    return c + (np.asarray(v, dtype=np.float64) - a) * (d - c) / (b - a)


@dataclass
class ModelB:
    """The density and light parameters (the shader's uniforms, thesis names, GLSL defaults)."""

    bounds_min: tuple = (-1500.0, 1000.0, -1500.0)
    bounds_max: tuple = (1500.0, 1400.0, 1500.0)
    cloud_scale: float = 0.6
    density_threshold: float = -5.0
    density_multiplier: float = 1.0
    detail_noise_multiplier: float = 0.5
    container_edge_fade_dst: float = 200.0
    volume_noise_weight: tuple = (1.0, 0.48, 0.15, 0.0)
    detail_noise_weight: tuple = (1.0, 0.5, 0.25)
    num_steps_light: int = 8
    light_absortion_sun: float = 0.03
    darkness_threshold: float = 0.2
    cloud_offset: tuple = (0.0, 0.0, 0.0)
    coverage_shift: tuple = (0.0, 0.0)  # metres (x, z); ``coverage`` receives p − shift
    weather_coverage: float = 0.0  # beyond the thesis: the map's coverage also thins the shape
    volume: Callable = field(default=lambda q: np.full(np.shape(q)[:-1] + (4,), 0.5))
    detail: Callable = field(default=lambda q: np.full(np.shape(q)[:-1] + (3,), 0.5))
    coverage: Callable = field(default=lambda p: np.full(np.shape(p)[:-1], 0.5))

    @classmethod
    def from_params(cls, params, **kw) -> "ModelB":
        names = [f for f in cls.__dataclass_fields__ if f not in ("volume", "detail", "coverage")]
        values = {n: params[f"clouds_b.{n}"] for n in names if f"clouds_b.{n}" in params}
        values.update(kw)
        return cls(**values)

    def edge_weight(self, p) -> np.ndarray:
        p = np.asarray(p, dtype=np.float64)
        lo, hi = np.asarray(self.bounds_min), np.asarray(self.bounds_max)
        fade = self.container_edge_fade_dst
        edge_x = np.minimum(fade, np.minimum(p[..., 0] - lo[0], hi[0] - p[..., 0]))
        edge_z = np.minimum(fade, np.minimum(p[..., 2] - lo[2], hi[2] - p[..., 2]))
        return np.maximum(np.minimum(edge_x, edge_z), 0.0) / fade

    @staticmethod
    def height_gradient(height_percent, gradient) -> np.ndarray:
        g_min = remap(gradient, 0.0, 1.0, 0.1, 0.5)
        g_max = remap(gradient, 0.0, 1.0, g_min, 0.9)
        return np.clip(remap(height_percent, 0.0, g_min, 0.0, 1.0), 0, 1) * \
            np.clip(remap(height_percent, 1.0, g_max, 0.0, 1.0), 0, 1)

    def envelope(self, p) -> np.ndarray:
        """heightGradient · edgeWeight at p (what multiplies the volume fBm)."""
        p = np.asarray(p, dtype=np.float64)
        lo, hi = np.asarray(self.bounds_min), np.asarray(self.bounds_max)
        h = (p[..., 1] - lo[1]) / (hi[1] - lo[1])
        shifted = p - np.array([self.coverage_shift[0], 0.0, self.coverage_shift[1]])
        gradient = self.coverage(shifted)
        return (self.height_gradient(h, gradient) * self.edge_weight(p)
                * self.weather_cover(gradient, self.weather_coverage))

    @staticmethod
    def weather_cover(gradient, amount: float) -> np.ndarray:
        """Beyond the thesis (CloudsBWeatherCover): mix(1, smoothstep(0.3, 0.7, gradient),
        amount) — the weather map's coverage on the base shape (1 at amount 0, the thesis)."""
        t = np.clip((np.asarray(gradient, dtype=np.float64) - 0.3) / 0.4, 0.0, 1.0)
        return 1.0 + (t * t * (3.0 - 2.0 * t) - 1.0) * amount

    def sample_position(self, p) -> np.ndarray:
        lo, hi = np.asarray(self.bounds_min), np.asarray(self.bounds_max)
        return (0.5 * (hi - lo) + np.asarray(p, dtype=np.float64)) * self.cloud_scale * 0.001

    def sample_density(self, p) -> np.ndarray:
        """sampleDensity(p) of spec/000 §A.4 and spec/000 §A.5."""
        p = np.asarray(p, dtype=np.float64)
        q = self.sample_position(p)
        off = np.asarray(self.cloud_offset, dtype=np.float64)
        wv = np.asarray(self.volume_noise_weight, dtype=np.float64)
        wv = wv / max(wv.sum(), 1e-6)
        volume_fbm = (self.volume(q + off * 0.1) @ wv) * self.envelope(p)
        volume_density = volume_fbm + self.density_threshold * 0.1
        wd = np.asarray(self.detail_noise_weight, dtype=np.float64)
        wd = wd / max(wd.sum(), 1e-6)
        detail_fbm = self.detail(q + off * 0.2) @ wd
        erode = (1.0 - volume_fbm) ** 3
        detail_density = (1.0 - detail_fbm) * erode * self.detail_noise_multiplier
        return np.where(volume_density > 0.0,
                        volume_density - detail_density * self.density_multiplier, 0.0)

    def light_at_pos(self, p, toward_sun) -> np.ndarray:
        """spec/000 §A.6: lightAtPos with the fix (L passed to rayBoxDistance itself); p (…, 3)."""
        p = np.array(p, dtype=np.float64)
        L = np.asarray(toward_sun, dtype=np.float64)
        d_in = ray_box_distance(self.bounds_min, self.bounds_max, p, L)[..., 1]
        step = d_in / self.num_steps_light
        p = p + L * (step * 0.5)[..., None]
        total = np.zeros(p.shape[:-1])
        for _ in range(self.num_steps_light):
            total += np.maximum(0.0, self.sample_density(p) * step)
            p = p + L * step[..., None]
        t = beer(total * self.light_absortion_sun)
        return self.darkness_threshold + t * (1.0 - self.darkness_threshold)


def wind_offset(base_offset, wind_xz, time_s: float, cloud_scale: float) -> np.ndarray:
    """_CloudOffset that moves the base shape with ``wind_xz`` (m/s along x and z): the base
    noise is sampled at (halfSize + p)·scale·0.001 + offset·0.1, so a world shift of w·t needs
    offset = −w·t·scale·0.01 (the detail noise, at offset·0.2, drifts twice as fast)."""
    w = np.asarray(wind_xz, dtype=np.float64)
    shift = np.array([w[0], 0.0, w[1]]) * float(time_s)
    return np.asarray(base_offset, dtype=np.float64) - shift * float(cloud_scale) * 0.01


def depth_for_distance(distance, ray_dir, forward, near: float, far: float) -> np.ndarray:
    """Window depth [0, 1] of a point ``distance`` along unit ``ray_dir`` (inverse of the
    shader's SceneDistance), for tests that fill a depth buffer."""
    eye = np.asarray(distance, dtype=np.float64) * (np.asarray(ray_dir) @ np.asarray(forward))
    z_ndc = (far + near - 2.0 * near * far / eye) / (far - near)
    return 0.5 * z_ndc + 0.5
