"""Shared maths, the numpy side of ``glsl/common/math.glsl``: one home for the constants, the
normalisers, the smoothsteps, the angle wraps, the compass (wind) convention and the camera
matrices, so that no effect or twin writes its own copy.

Each function keeps the exact arithmetic of the copies it replaced (the same operations in the
same order), so the pinned renders stay bit-identical. ``tests/gl/test_maths_twin.py`` checks the
twins against math.glsl on the GPU, ``tests/unit/test_maths.py`` the matrices against pyrr.

The compass convention, everywhere in the project: a wind (or a heading, a facing) of
``degrees`` points *toward* that compass direction, 0 = north = −z, 90 = east = +x; its unit
(x, z) vector is (sin a, −cos a)."""

from __future__ import annotations

import math

import numpy as np

#: π, 2π and π/2: the constants of glsl/common/math.glsl (PI, TWO_PI, HALF_PI)
PI = math.pi
TWO_PI = 2.0 * math.pi
HALF_PI = 0.5 * math.pi


def saturate(x):
    """Twin of ``saturate`` (math.glsl, spec/001 eq. 4.2): clamp(x, 0, 1), as float64."""
    return np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)


def smoothstep(e0, e1, x):
    """Twin of GLSL ``smoothstep(e0, e1, x)`` [e0 < e1]: t²(3 − 2t), t = clamp((x − e0) /
    (e1 − e0), 0, 1). Failure case: e0 ≥ e1 is undefined in GLSL (use ``smoothstep_down``)."""
    # the clamp as the two ufuncs it is (np.clip's argument handling costs more, in the
    # sailing's inner loop); a −0 it may keep is squared away, so np.clip's values exactly
    t = np.minimum(np.maximum((np.asarray(x, dtype=np.float64) - e0) / (e1 - e0), 0.0), 1.0)
    return t * t * (3.0 - 2.0 * t)


def smoothstep_down(hi, lo, x):
    """Twin of ``SmoothStepDown(hi, lo, x)`` (math.glsl): 1 − smoothstep(lo, hi, x), the
    reversed ramp HLSL writes smoothstep(hi, lo, x); 1 at x ≤ lo, 0 at x ≥ hi."""
    return 1.0 - smoothstep(lo, hi, x)


def normalize(v, axis: int | None = -1) -> np.ndarray:
    """``v`` over its length along ``axis`` (``axis=None``: the whole vector, √(v·v), as
    ``numpy.linalg.norm(v)``). Failure case: a zero vector gives NaN, as GLSL ``normalize``;
    use ``safe_normalize`` where one can occur."""
    v = np.asarray(v)
    if axis is None:
        return v / np.linalg.norm(v)
    return v / np.linalg.norm(v, axis=axis, keepdims=True)


def unit_vectors(v, fallback=None, eps: float = 1e-12) -> tuple[np.ndarray, np.ndarray]:
    """(unit vectors along the last axis, ok mask): rows of length ≤ ``eps`` or not finite
    become ``fallback`` (zero when None), never NaN."""
    v = np.asarray(v, np.float64)
    with np.errstate(over="ignore", invalid="ignore"):
        length = np.linalg.norm(v, axis=-1)
        ok = np.isfinite(length) & (length > eps)
        out = np.divide(v, length[..., None], out=np.zeros_like(v), where=ok[..., None])
    if fallback is not None:
        out[~ok] = fallback
    return out, ok


def safe_normalize(v, fallback=None, eps: float = 1e-10) -> np.ndarray:
    """Twin of ``SafeNormalize(x, fallback)`` (math.glsl): unit vectors along the last axis,
    ``fallback`` (zero when None) where the length is ≤ ``eps`` or not finite."""
    return unit_vectors(v, fallback, eps)[0]


def wrap_two_pi(angle):
    """``angle`` [rad] wrapped into [0, 2π): angle − 2π ⌊angle / 2π⌋ (GLSL ``mod(a, TWO_PI)``)."""
    return angle - TWO_PI * np.floor(angle / TWO_PI)


def wrap_degrees(angle):
    """An angle [degrees] wrapped into (−180, 180] (a float for a scalar)."""
    a = np.asarray(angle, dtype=np.float64)
    out = 180.0 - np.mod(180.0 - a, 360.0)
    return float(out) if out.ndim == 0 else out


def compass_xz(degrees: float) -> np.ndarray:
    """The unit (x, z) vector toward compass ``degrees`` (0 = north = −z, 90 = east = +x): the
    direction a wind of that direction blows toward."""
    a = math.radians(degrees)
    return np.array([math.sin(a), -math.cos(a)])


def direction(elevation_deg, azimuth_deg) -> np.ndarray:
    """Unit vector at an elevation above the local horizon and an azimuth (0 = north = −z,
    90 = east = +x), y up — as a scene's sun and the camera's yaw. Vectorised: (..., 3)."""
    e = np.radians(np.asarray(elevation_deg, dtype=np.float64))
    a = np.radians(np.asarray(azimuth_deg, dtype=np.float64))
    e, a = np.broadcast_arrays(e, a)
    return np.stack([np.sin(a) * np.cos(e), np.sin(e), -np.cos(a) * np.cos(e)], axis=-1)


def compass_radians(x: float, z: float) -> float:
    """The compass angle [rad, in (−π, π]] of the (x, z) vector: atan2(x, −z), the inverse of
    ``compass_xz``."""
    return math.atan2(x, -z)


def compass_degrees(x: float, z: float) -> float:
    """The compass direction [degrees, in [0, 360)] the (x, z) vector points toward."""
    return math.degrees(compass_radians(x, z)) % 360.0


def rotation_y(theta: float) -> np.ndarray:
    """spec/003 eq. 7.9: R_y(θ) = [[cos θ, 0, sin θ], [0, 1, 0], [−sin θ, 0, cos θ]] [θ in rad]."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def look_at(eye, target, up) -> np.ndarray:
    """World → view matrix (right-handed, looking down −z; M @ v) of a camera at ``eye`` looking
    at ``target``. Failure case: ``up`` parallel to the view falls back to +x."""
    f = np.asarray(target, float) - np.asarray(eye, float)
    f /= np.linalg.norm(f)
    r = np.cross(f, up)
    if np.linalg.norm(r) < 1e-6:
        r = np.cross(f, [1.0, 0.0, 0.0])
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    m = np.identity(4)
    m[0, :3], m[1, :3], m[2, :3] = r, u, -f
    m[:3, 3] = -m[:3, :3] @ np.asarray(eye, float)
    return m


def perspective(fovy_deg: float, aspect: float, near: float, far: float) -> np.ndarray:
    """OpenGL perspective projection (M @ v) of vertical field of view ``fovy_deg`` [degrees]."""
    f = 1.0 / np.tan(np.radians(fovy_deg) / 2.0)
    m = np.zeros((4, 4))
    m[0, 0], m[1, 1] = f / aspect, f
    m[2, 2] = (far + near) / (near - far)
    m[2, 3] = 2 * far * near / (near - far)
    m[3, 2] = -1.0
    return m


def merged_runs(start, count, picked) -> list[tuple[int, int]]:
    """(first, count) runs of the items ``picked`` (item k: ``count[k]`` elements from
    ``start[k]``), in their order, neighbours in the buffer merged into one run."""
    runs: list[tuple[int, int]] = []
    for k in picked:
        s, c = int(start[k]), int(count[k])
        if runs and runs[-1][0] + runs[-1][1] == s:
            runs[-1] = (runs[-1][0], runs[-1][1] + c)
        else:
            runs.append((s, c))
    return runs
