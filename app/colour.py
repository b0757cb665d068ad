"""Colour: sRGB transfer functions and the tone maps of the display pass.

:func:`tonemap` and :func:`linear_to_srgb` are the numpy twins of ``glsl/common/tonemap.glsl``
(the window's display pass), so a PNG written headless matches the window pixel for pixel.
"""

from __future__ import annotations

import numpy as np

from .errors import UsageError

TONEMAPS = ("aces", "reinhard", "clamp", "exponential")
#: Rec. 709 luminance weights of linear RGB
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def tonemap_aces(x: np.ndarray) -> np.ndarray:
    """Narkowicz's fit of the ACES filmic curve (2015)."""
    a, b, c, d, e = 2.51, 0.03, 2.43, 0.59, 0.14
    return np.clip((x * (a * x + b)) / (x * (c * x + d) + e), 0.0, 1.0)


def linear_to_srgb(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


def srgb_to_linear(x: np.ndarray) -> np.ndarray:
    x = np.asarray(x, dtype=np.float64)
    return np.where(x <= 0.04045, x / 12.92, ((x + 0.055) / 1.055) ** 2.4)


def tonemap(rgb: np.ndarray, exposure: float = 1.0, mode: str = "aces") -> np.ndarray:
    """Linear radiance → display-linear [0, 1]. NaN/Inf become 0 / 1 rather than spreading."""
    if mode not in TONEMAPS:
        raise UsageError(f"tone map {mode!r} is unknown: allowed {', '.join(TONEMAPS)}")
    x = np.nan_to_num(np.asarray(rgb, dtype=np.float64), nan=0.0, posinf=1e6, neginf=0.0)
    x = np.maximum(x * exposure, 0.0)
    if mode == "aces":
        return tonemap_aces(x)
    if mode == "reinhard":
        return x / (1.0 + x)
    if mode == "exponential":  # O'Neil's exposure, used by the atmosphere thesis (spec/002 §1.6)
        return 1.0 - np.exp(-x)
    return np.clip(x, 0.0, 1.0)


def to_srgb8(rgb: np.ndarray, exposure: float = 1.0, mode: str = "aces") -> np.ndarray:
    return np.round(linear_to_srgb(tonemap(rgb, exposure, mode)) * 255.0).astype(np.uint8)
