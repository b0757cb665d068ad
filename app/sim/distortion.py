"""The refraction's distortion texture, made by code (spec/003 §2.7: the thesis's "Distortion
Texture (a bump map)"): a tileable tangent-space field xy ∈ [−1, 1]² — the gradient of a sum of
random periodic ripples, normalised to peak 1 — that ``DistortNormal`` (glsl/surfaces/
refraction.glsl) adds along the tangent frame. Stored as RG8 by :func:`encode` (tex = (xy + 1)/2,
the shader unpacks d = 2·tex − 1).
"""

from __future__ import annotations

import numpy as np


def distortion_map(size: int = 128, waves: int = 12, seed: int = 0) -> np.ndarray:
    """(size, size, 2) float32 in [−1, 1]: −∇h of h = Σ aᵢ sin(2π(kᵢ·uv) + φᵢ) with integer
    wave vectors kᵢ (so it tiles), |kᵢ| ≤ 6, aᵢ ∝ 1/|kᵢ|, scaled so max |xy| = 1."""
    if not isinstance(size, int) or size < 4:
        raise ValueError(f"size={size!r}: must be an int ≥ 4")
    if not isinstance(waves, int) or waves < 1:
        raise ValueError(f"waves={waves!r}: must be an int ≥ 1")
    rng = np.random.default_rng(seed)
    u = (np.arange(size) + 0.5) / size
    uu, vv = np.meshgrid(u, u)
    gx = np.zeros_like(uu)
    gy = np.zeros_like(uu)
    for _ in range(waves):
        k = rng.integers(-6, 7, size=2)
        while not k.any():
            k = rng.integers(-6, 7, size=2)
        a = 1.0 / float(np.hypot(*k))
        phase = 2.0 * np.pi * (k[0] * uu + k[1] * vv) + rng.uniform(0.0, 2.0 * np.pi)
        c = a * 2.0 * np.pi * np.cos(phase)
        gx += c * k[0]
        gy += c * k[1]
    xy = -np.stack([gx, gy], axis=-1)
    peak = float(np.abs(xy).max())
    return (xy / peak).astype(np.float32)


def encode(xy: np.ndarray) -> np.ndarray:
    """RG8 texels (xy + 1)/2 · 255, rounded; the shader's 2·tex − 1 gives xy back to 1/255."""
    xy = np.asarray(xy, dtype=np.float64)
    if xy.ndim != 3 or xy.shape[-1] != 2:
        raise ValueError(f"xy shape {xy.shape}: must be (h, w, 2)")
    return np.round((np.clip(xy, -1.0, 1.0) + 1.0) * 0.5 * 255.0).astype(np.uint8)
