"""The staircase functions of the toon look (spec/003 §2.10, §2.13): the numpy twin of
``glsl/common/staircase.glsl``, one function per GLSL function (snake case), float64 and
vectorised over arrays. See the GLSL file's header for the equations and the guards (the same
here); ``x mod s`` is GLSL's ``mod``, ``x − s·floor(x/s)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

Array = NDArray[np.float64]


def _mod(x: ArrayLike, s: ArrayLike) -> Array:
    """GLSL's mod: x − s·floor(x/s)."""
    xa = np.asarray(x, dtype=np.float64)
    sa = np.asarray(s, dtype=np.float64)
    return xa - sa * np.floor(xa / sa)


def staircase_safe_step(step_x: ArrayLike) -> Array:
    """step_x clamped into [1e-4, 1 − 1e-4] (no division by zero in
    spec/003 eq. 7.18 and spec/003 eq. 7.19)."""
    return np.clip(np.asarray(step_x, dtype=np.float64), 1e-4, 1.0 - 1e-4)


def staircase_step_y(step_x: ArrayLike) -> Array:
    """spec/003 eq. 7.18: step_y = step_x / (1 − step_x)."""
    s = staircase_safe_step(step_x)
    return s / (1.0 - s)


def staircase_floor(x: ArrayLike, step_x: ArrayLike) -> Array:
    """spec/003 eq. 7.19: x − (x mod step_x)."""
    s = staircase_safe_step(step_x)
    xa = np.asarray(x, dtype=np.float64)
    return xa - _mod(xa, s)


def staircase_level(x_floored: ArrayLike, step_x: ArrayLike) -> Array:
    """spec/003 eq. 7.20: (x / step_x) · step_y."""
    return np.asarray(x_floored, dtype=np.float64) / staircase_safe_step(step_x) \
        * staircase_step_y(step_x)


def staired_value(x: ArrayLike, step_x: ArrayLike) -> Array:
    """The colour discretisation (GetStairedValue): spec/003 eq. 7.19 then
    spec/003 eq. 7.20, clamped to 1."""
    return np.minimum(staircase_level(staircase_floor(x, step_x), step_x), 1.0)


def soft_stair_weight_min(d: ArrayLike, step_soft: ArrayLike) -> Array:
    """spec/003 eq. 8.2: weight_min = ½ − d/step_soft (the division saturated)."""
    ss = np.maximum(np.asarray(step_soft, dtype=np.float64), 1e-8)
    return 0.5 - np.clip(np.asarray(d, dtype=np.float64) / ss, 0.0, 1.0)


def soft_stair_weight_max(d: ArrayLike, step: ArrayLike, step_soft: ArrayLike) -> Array:
    """spec/003 eq. 8.3: weight_max = ½ − (step − d)/step_soft (the division saturated)."""
    ss = np.maximum(np.asarray(step_soft, dtype=np.float64), 1e-8)
    return 0.5 - np.clip((np.asarray(step, dtype=np.float64) - np.asarray(d, dtype=np.float64))
                         / ss, 0.0, 1.0)


def soft_stair_offsets(d: ArrayLike, step: ArrayLike, step_soft: ArrayLike) -> Array:
    """spec/003 eq. 8.4: e_min + e_max, each only within half a soft step of its jump; zero
    for step_soft ≤ 0 (the hard staircase)."""
    da = np.asarray(d, dtype=np.float64)
    s = np.asarray(step, dtype=np.float64)
    ss = np.asarray(step_soft, dtype=np.float64)
    half = 0.5 * ss
    e_min = np.where(da < half, -s * soft_stair_weight_min(da, ss), 0.0)
    e_max = np.where(s - da < half, s * soft_stair_weight_max(da, s, ss), 0.0)
    return np.where(ss > 0.0, e_min + e_max, 0.0)


def soft_staired_value(x: ArrayLike, step: ArrayLike, step_soft: ArrayLike) -> Array:
    """The soft staircase (GetSoftStairedValue): saturate((x − d) + e_min + e_max), d = x mod
    step — the hard staircase of height ``step`` with each jump a ramp of width step_soft."""
    s = np.maximum(np.asarray(step, dtype=np.float64), 1e-4)
    xa = np.asarray(x, dtype=np.float64)
    d = _mod(xa, s)
    return np.clip(xa - d + soft_stair_offsets(d, s, step_soft), 0.0, 1.0)


def threshold_step(x: ArrayLike, threshold: ArrayLike) -> Array:
    """The first rim silhouette: 1 where x > threshold, else 0."""
    return (np.asarray(x, dtype=np.float64) > np.asarray(threshold, dtype=np.float64)) \
        .astype(np.float64)


def soft_silhouette(x: ArrayLike) -> Array:
    """The third rim silhouette: saturate(50·x²)."""
    xa = np.asarray(x, dtype=np.float64)
    return np.clip(50.0 * xa * xa, 0.0, 1.0)
