"""Twin of ``glsl/common/noise_value.glsl``: the procedural-wood thesis's lattice value noise
(spec/004 §1.5–1.6), vectorised over numpy arrays.

The random source is a seeded 256×256 RGB8 image (:func:`random_texture`); its texels are used as
``k / 255`` exactly as the GPU reads an RGBA8 texture.
"""

from __future__ import annotations

import numpy as np

TABLE_SIZE = 256


def random_texture(seed: int) -> np.ndarray:
    """The thesis's "Random Noise Source": 256×256 pseudo-random RGB, as uint8 RGBA (A = 255).
    Row index = texture v (y), column = u (x)."""
    rng = np.random.default_rng(int(seed))
    tex = rng.integers(0, 256, size=(TABLE_SIZE, TABLE_SIZE, 4), dtype=np.uint8)
    tex[..., 3] = 255
    return tex


def ease_in_out(x):
    """c(t) = 3t² − 2t³ with the thesis's clamps (0 below 0, 1 above 1)."""
    x = np.asarray(x, dtype=np.float64)
    return np.where(x <= 0.0, 0.0, np.where(x >= 1.0, 1.0, (3.0 - 2.0 * x) * x * x))


def ease_in(x):
    """g(t) = t², clamped to [0, 1] (the ring colour ramp distortion)."""
    x = np.asarray(x, dtype=np.float64)
    return np.where(x <= 0.0, 0.0, np.where(x >= 1.0, 1.0, x * x))


class ValueNoise:
    """The thesis's noise for one random texture. ``noise3`` and ``octaves`` take arrays of
    points with a trailing axis of 3 and return values in [0, 1]³."""

    def __init__(self, seed: int = 1, wrap: float = 256.0):
        self.texture = random_texture(seed)
        self.table = self.texture[..., :3].astype(np.float32) / np.float32(255.0)
        self.wrap = float(wrap)

    def get_pixel(self, indices: np.ndarray) -> np.ndarray:
        """The three chained lookups; ``indices`` are non-negative integers (..., 3)."""
        f = np.mod(np.asarray(indices, dtype=np.float32) / np.float32(256.0), np.float32(1.0))
        t = self.table

        def fetch(uv):
            idx = np.floor(uv * np.float32(256.0)).astype(np.int64) % TABLE_SIZE
            return t[idx[..., 1], idx[..., 0]]

        pix = fetch(f[..., 0:2])
        pix = fetch(np.mod(pix[..., 0:2] + f[..., 1:3], np.float32(1.0)))
        pix = fetch(np.mod(pix[..., 0:2] + f[..., [2, 0]], np.float32(1.0)))
        return pix.astype(np.float64)

    def noise3(self, p: np.ndarray) -> np.ndarray:
        p = np.asarray(p, dtype=np.float64)
        q = p - np.floor(p / self.wrap) * self.wrap
        i = np.floor(q)
        t = q - i
        w = ease_in_out(t)
        wx, wy, wz = (w[..., k : k + 1] for k in range(3))

        def c(dx, dy, dz):
            return self.get_pixel(i + np.array([dx, dy, dz], dtype=np.float64))

        c00 = c(0, 0, 0) * (1 - wz) + c(0, 0, 1) * wz
        c01 = c(0, 1, 0) * (1 - wz) + c(0, 1, 1) * wz
        c10 = c(1, 0, 0) * (1 - wz) + c(1, 0, 1) * wz
        c11 = c(1, 1, 0) * (1 - wz) + c(1, 1, 1) * wz
        c0 = c00 * (1 - wy) + c01 * wy
        c1 = c10 * (1 - wy) + c11 * wy
        return c0 * (1 - wx) + c1 * wx

    def octaves(self, p: np.ndarray, depth: int) -> np.ndarray:
        d = int(min(8, max(1, depth)))
        p = np.asarray(p, dtype=np.float64)
        total = sum(0.5**i for i in range(d))
        return sum(self.noise3(p * 2.0**i) * 0.5**i for i in range(d)) / total
