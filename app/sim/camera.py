"""A fly camera: position, yaw, pitch and vertical field of view.

Conventions (right-handed, y up, metres): yaw 0° looks north (−z), yaw 90° looks east (+x);
pitch is positive looking up. :meth:`Camera.ray_directions` is the numpy twin of
``CameraRayDirection`` in ``glsl/common/camera.glsl``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from pyrr import matrix44

from ..errors import UsageError, quote
from .maths import normalize
from .vec import cross


@dataclass
class Camera:
    position: tuple[float, float, float] = (0.0, 2.0, 0.0)
    yaw: float = 0.0
    pitch: float = 10.0
    fov: float = 60.0  # vertical, degrees
    near: float = 0.1
    far: float = 20000.0

    def __post_init__(self):
        self.position = tuple(float(v) for v in self.position)
        self.set(yaw=self.yaw, pitch=self.pitch, fov=self.fov)

    def set(self, position=None, yaw=None, pitch=None, fov=None) -> "Camera":
        if position is not None:
            pos = tuple(float(v) for v in position)
            if len(pos) != 3 or not all(math.isfinite(v) for v in pos):
                raise UsageError(f"camera position {position!r} is not three finite numbers: "
                                 "allowed X,Y,Z in metres")
            self.position = pos
        if yaw is not None:
            if not math.isfinite(yaw):
                raise UsageError(f"camera yaw {yaw!r} is not finite: allowed degrees")
            self.yaw = float(yaw) % 360.0
        if pitch is not None:
            if not (math.isfinite(pitch) and -90.0 <= pitch <= 90.0):
                raise UsageError(f"camera pitch {pitch!r} is out of range: "
                                 "allowed [-90, 90] degrees")
            self.pitch = float(pitch)
        if fov is not None:
            if not (math.isfinite(fov) and 1.0 <= fov <= 170.0):
                raise UsageError(f"camera fov {fov!r} is out of range: allowed [1, 170] degrees")
            self.fov = float(fov)
        return self

    def forward(self) -> np.ndarray:
        y, p = math.radians(self.yaw), math.radians(self.pitch)
        return np.array([math.sin(y) * math.cos(p), math.sin(p), -math.cos(y) * math.cos(p)])

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(right, up, forward), orthonormal. Looking straight up or down keeps yaw's right."""
        f = self.forward()
        y = math.radians(self.yaw)
        right = np.array([math.cos(y), 0.0, math.sin(y)])
        up = cross(right, f)  # numpy.cross's products, without its per-call overhead
        return right, normalize(up, axis=None), f

    def look_at_direction(self, direction) -> "Camera":
        d = normalize(np.asarray(direction, dtype=float), axis=None)
        pitch = math.degrees(math.asin(max(-1.0, min(1.0, d[1]))))
        yaw = math.degrees(math.atan2(d[0], -d[2]))
        return self.set(yaw=yaw, pitch=pitch)

    def move(self, forward: float = 0.0, right: float = 0.0, up: float = 0.0) -> None:
        r, _, f = self.basis()
        p = np.asarray(self.position) + f * forward + r * right + np.array([0.0, up, 0.0])
        self.position = tuple(float(v) for v in p)

    def rotate(self, dyaw: float, dpitch: float) -> None:
        self.yaw = (self.yaw + dyaw) % 360.0
        self.pitch = max(-89.9, min(89.9, self.pitch + dpitch))

    def view_matrix(self) -> np.ndarray:
        r, u, f = self.basis()
        eye = np.asarray(self.position)
        m = np.identity(4)
        m[0, :3], m[1, :3], m[2, :3] = r, u, -f
        m[:3, 3] = -m[:3, :3] @ eye
        return m

    def projection_matrix(self, aspect: float) -> np.ndarray:
        # pyrr builds the transposed (row-vector) form; transpose to M @ v.
        return matrix44.create_perspective_projection(self.fov, aspect, self.near, self.far,
                                                      dtype=np.float64).T

    def view_projection_relative(self, aspect: float) -> np.ndarray:
        """Projection × view for camera-relative positions (world − camera position): the
        transform every pass that keeps float32 exact far from the origin shares, so their
        depths agree where their surfaces meet."""
        view = self.view_matrix().copy()
        view[:3, 3] = 0.0
        return self.projection_matrix(aspect) @ view

    def ray_directions(self, width: int, height: int) -> np.ndarray:
        """World-space unit view directions through pixel centres, row 0 at the top."""
        r, u, f = self.basis()
        t = math.tan(math.radians(self.fov) * 0.5)
        aspect = width / height
        xs = ((np.arange(width) + 0.5) / width * 2.0 - 1.0) * t * aspect
        ys = (1.0 - (np.arange(height) + 0.5) / height * 2.0) * t
        d = (f[None, None, :] + xs[None, :, None] * r[None, None, :]
             + ys[:, None, None] * u[None, None, :])
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    def uniforms(self, aspect: float) -> dict:
        r, u, f = self.basis()
        return {
            "uCameraPos": tuple(self.position),
            "uCamRight": tuple(r),
            "uCamUp": tuple(u),
            "uCamForward": tuple(f),
            "uTanHalfFov": math.tan(math.radians(self.fov) * 0.5),
            "uAspect": aspect,
        }


def parse_camera(text: str, camera: Camera | None = None) -> Camera:
    """``--camera X,Y,Z[,YAW[,PITCH[,FOV]]]``."""
    cam = camera or Camera()
    allowed = "allowed X,Y,Z[,YAW[,PITCH[,FOV]]] (metres, then degrees)"
    if not text.strip():
        raise UsageError(f"--camera {quote(text)} is empty: {allowed}")
    parts = text.replace(" ", "").split(",")
    if not 3 <= len(parts) <= 6:
        raise UsageError(f"--camera {quote(text)} has {len(parts)} parts: {allowed}")
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise UsageError(f"--camera {quote(text)} is not numbers: {allowed}") from None
    if not all(math.isfinite(v) for v in values):
        raise UsageError(f"--camera {quote(text)} is not finite numbers: {allowed}")
    cam.set(position=values[:3])
    names = ("yaw", "pitch", "fov")
    cam.set(**{n: v for n, v in zip(names, values[3:])})
    return cam
