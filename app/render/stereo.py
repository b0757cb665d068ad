"""Side-by-side stereo for a scene's VR mode (spec/003 §2.15): each eye gets its own view — the
head's camera moved by half the interpupillary distance along its right vector, parallel axes —
and its own projection (the eye's half of the frame: aspect (W/2)/H), is rendered into its own
render texture at ``render_scale`` of its half (Unity's eye texture resolution scale: cheaper
below 1, supersampled above), and is copied into its half of the frame, left eye on the left.

:func:`eye_cameras` is plain numpy (the mono render from one eye's camera at the eye's size is
what that eye shows: at render scale 1 the copy is exact, texel for pixel); :class:`StereoRenderer`
does the GL side for any ``render_eye(frame, target)``.

Odd widths: the left half gets ⌊W/2⌋ pixels, the right one the rest, and each eye's texture is
sized from its own half (so at render scale 1 neither is stretched). A frame 1 pixel wide has
an empty left half: only the right eye is rendered and shown. Each eye texture is at least
1 × 1. The copy filters bilinearly: below scale 1 it magnifies; above 1 it minifies from the
four nearest texels (a 2 × 2 box at scale 2, exact supersampling; between 1 and 2 it skips
some texels).
"""

from __future__ import annotations

import dataclasses
from typing import Any, Callable

import moderngl
import numpy as np

from ..gpu.programs import draw_fullscreen, fullscreen
from ..sim.camera import Camera

EYE_COPY = fullscreen("common/eye_copy")
EYES = ("left", "right")


def _check_eye(eye: str) -> str:
    if eye not in EYES:
        raise ValueError(f"eye {eye!r}: allowed {', '.join(EYES)}")
    return eye


def eye_camera(camera: Camera, ipd: float, eye: str) -> Camera:
    """The camera of one eye: ``camera`` moved by ∓ipd/2 along its right vector (left eye to
    the left), same orientation, field of view and planes."""
    _check_eye(eye)
    right, _, _ = camera.basis()
    sign = -1.0 if eye == "left" else 1.0
    pos = np.asarray(camera.position, np.float64) + sign * 0.5 * float(ipd) * right
    return Camera(position=tuple(pos), yaw=camera.yaw, pitch=camera.pitch, fov=camera.fov,
                  near=camera.near, far=camera.far)


def eye_cameras(camera: Camera, ipd: float) -> tuple[Camera, Camera]:
    return eye_camera(camera, ipd, "left"), eye_camera(camera, ipd, "right")


def eye_viewport(size: tuple[int, int], eye: str) -> tuple[int, int, int, int]:
    """(x, y, w, h) of one eye's half of a frame of ``size`` (the left one gets the floor; in
    a frame 1 pixel wide it is empty)."""
    _check_eye(eye)
    w, h = int(size[0]), int(size[1])
    half = w // 2
    return (0, 0, half, h) if eye == "left" else (half, 0, w - half, h)


def eye_size(size: tuple[int, int], render_scale: float = 1.0,
             eye: str = "left") -> tuple[int, int]:
    """The render texture of one eye: its half of the frame (:func:`eye_viewport`) times
    ``render_scale``, rounded, at least 1 × 1."""
    s = float(render_scale)
    _, _, w, h = eye_viewport(size, eye)
    return max(1, int(round(w * s))), max(1, int(round(h * s)))


class StereoRenderer:
    """Renders a frame once per eye into per-eye targets (kept while their size holds) and
    composes them side by side into the frame's target."""

    def __init__(self, gpu, owner: str):
        self.gpu, self.owner = gpu, owner
        self.targets: dict[str, Any] = {}
        #: the eye cameras of the last frame rendered (tests and the bench compare with them)
        self.last_eyes: dict[str, Camera] = {}

    def _target(self, eye: str, size: tuple[int, int]):
        t = self.targets.get(eye)
        if t is None or tuple(t.size) != tuple(size):
            if t is not None:
                self.gpu.free(t)
            t = self.gpu.target(self.owner, f"{eye} eye", size)
            self.targets[eye] = t
        return t

    def render(self, frame, target, ipd: float, render_scale: float,
               render_eye: Callable[[object, object], None]) -> None:
        """Each eye's ``render_eye(eye_frame, eye_target)`` — ``frame`` with the eye's camera
        and size, ``eye`` set, ``image`` unset (the scene sets it to the eye's target) — then
        both composed into ``target`` (``ipd`` and ``render_scale``: the ranges of the vr.ipd
        and vr.render_scale Params)."""
        eyes = {}
        shown = [e for e in EYES if eye_viewport(target.size, e)[2] > 0]
        for eye in shown:
            cam = eye_camera(frame.camera, ipd, eye)
            eyes[eye] = cam
            size = eye_size(target.size, render_scale, eye)
            # the frame as that eye sees it: its camera, its size; slots filled this frame
            # (lights, shadows, terrain...) are shared
            eye_frame = dataclasses.replace(frame, camera=cam, size=size, eye=eye, image=None)
            render_eye(eye_frame, self._target(eye, size))
        self.last_eyes = eyes
        ctx = self.gpu.ctx
        prog = self.gpu.program(self.owner, EYE_COPY)
        target.use()
        target.clear((0.0, 0.0, 0.0, 1.0))  # every pixel is then covered: depth left at far
        ctx.disable(moderngl.DEPTH_TEST)
        ctx.disable(moderngl.BLEND)
        try:
            for eye in shown:
                prog.bind_textures({"uEye": self.targets[eye].color})
                ctx.viewport = eye_viewport(target.size, eye)
                draw_fullscreen(prog)
        finally:
            ctx.viewport = (0, 0, *target.size)

    def release(self) -> None:
        for t in self.targets.values():
            self.gpu.free(t)
        self.targets = {}
