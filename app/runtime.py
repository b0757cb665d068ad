"""Opening a scene and rendering it headless: shared by the CLI, the bench and the tests."""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Generator, Iterable

import numpy as np

from .errors import UsageError, quote
from .gpu.device import Gpu
from .gpu.shaders import ShaderLibrary, resolve_shader_root
from .gpu.targets import check_frame_size
from .params import ParamSet
from .scenes import get_scene
from .scenes.base import Scene
from .sim.camera import Camera, parse_camera

MAX_SIDE = 16384
_SIZE = re.compile(r"\s*(\d{1,9})\s*[xX×]\s*(\d{1,9})\s*")


def parse_size(text: str, option: str = "--size") -> tuple[int, int]:
    """``WxH`` with each side in [1, 16384]; what the renderer can hold is checked when a
    session opens (``app.gpu.targets.check_frame_size``: its side limits and memory)."""
    m = _SIZE.fullmatch(text) if text.isascii() or "×" in text else None
    if not m:
        what = "is empty" if not text.strip() else "is not WxH"
        raise UsageError(f"{option} {quote(text)} {what}: allowed WxH, e.g. 1280x720")
    w, h = int(m[1]), int(m[2])
    if not (1 <= w <= MAX_SIDE and 1 <= h <= MAX_SIDE):
        raise UsageError(f"{option} {quote(text)} is out of range: "
                         f"allowed 1..{MAX_SIDE} on each side")
    return w, h


@dataclass
class Session:
    gpu: Gpu
    scene: Scene
    params: ParamSet

    def release(self) -> None:
        self.scene.release()
        self.gpu.release()

    def __enter__(self) -> Session:
        return self

    def __exit__(self, *exc) -> None:
        self.release()


def scene_params(scene_name: str, shader_root=None, sets: Iterable[str] = (),
                 preset: str | None = None, view=None) -> ParamSet:
    """Validate a scene's parameters without touching the GPU (annotations are read from the
    GLSL files directly): the scene's defaults, then ``view``'s (an ``app.scenes.views.View``),
    then ``preset``, then ``sets``; then the rules between parameters (their ``Joint``s)."""
    cls = get_scene(scene_name)
    library = ShaderLibrary(None, resolve_shader_root(shader_root))
    params = cls.declare_params(library)
    if view is not None:
        view.apply(params)
    if preset:
        params.load_preset(Path(preset))
    for assignment in sets:
        params.set_from_string(assignment)
    params.check_joint()  # the rules between parameters, once every value is in
    return params


def placed_camera(scene_name: str, params: ParamSet, view=None,
                  camera_text: str | None = None) -> Camera:
    """The scene's camera, placed by ``view`` (a ``scenes.views`` view) and then by
    ``camera_text`` (``X,Y,Z[,YAW[,PITCH[,FOV]]]``, checked against the scene's range), either
    of which tells the scene the user placed it (a chase camera lets go)."""
    cls = get_scene(scene_name)
    camera = cls.new_camera()
    if view is not None and view.place(camera):
        cls.on_user_camera(params)
    if camera_text is not None:
        parse_camera(camera_text, camera)
        cls.check_camera(camera)
        cls.on_user_camera(params)
    return camera


def open_session(scene_name: str, params: ParamSet | None = None, shader_root=None, ctx=None,
                 camera: Camera | None = None,
                 sizes: Iterable[tuple[int, int]] = ()) -> Session:
    """A scene on a GPU. ``sizes``: the frame sizes it will render, refused before the scene
    is built when the context cannot hold them (``app.gpu.targets.TargetSizeError``)."""
    cls = get_scene(scene_name)
    root = resolve_shader_root(shader_root)
    if params is None:
        params = scene_params(scene_name, root)
    gpu = Gpu(ctx, root)
    try:
        for size in sizes:
            check_frame_size(gpu.ctx, size)
        return Session(gpu, cls(gpu, params, camera), params)
    except BaseException:
        gpu.release()
        raise


def render_frames(session: Session, size: tuple[int, int], frames: int = 1, fps: float = 30.0,
                  progress: bool = False, warmup: int = 0) -> Generator[np.ndarray, None, None]:
    """Yield ``frames`` linear-radiance images ``(h, w, 4)``; time advances 1/fps per frame.
    ``warmup`` frames are rendered first and not yielded (a view that needs the boat to
    settle or a temporal filter to converge)."""
    dt = 1.0 / fps
    target = session.gpu.target("output", "scene radiance", size)
    try:
        for i in range(warmup):
            session.scene.render(session.scene.frame(size, dt=0.0 if i == 0 else dt), target)
        for i in range(frames):
            frame = session.scene.frame(size, dt=0.0 if i == 0 and not warmup else dt)
            session.scene.render(frame, target)
            image = target.read()
            if progress:  # before the yield: a consumer may never resume after the last frame
                _progress(i + 1, frames)
            yield image
    finally:
        session.gpu.free(target)
        if progress:
            end_progress()


_progress_open = False


def _progress(done: int, total: int, width: int = 30) -> None:
    """One progress line on stderr, redrawn in place; :func:`end_progress` ends it, so what
    follows on the terminal (the written paths on stdout) starts on a line of its own."""
    global _progress_open
    filled = int(width * done / total)
    sys.stderr.write(f"\rrendering [{'#' * filled}{'.' * (width - filled)}] {done}/{total} frames")
    sys.stderr.flush()
    _progress_open = True


def end_progress() -> None:
    """End the progress line (once; harmless when none is open)."""
    global _progress_open
    if _progress_open:
        sys.stderr.write("\n")
        sys.stderr.flush()
        _progress_open = False
