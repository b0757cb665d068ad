"""Opening a scene and rendering it headless: shared by the CLI, the bench and the tests."""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, Iterator

import numpy as np

from .errors import UsageError
from .gpu.device import Gpu
from .gpu.shaders import ShaderLibrary, resolve_shader_root
from .params import ParamSet
from .scenes import get_scene
from .scenes.base import Scene
from .sim.camera import Camera


def parse_size(text: str) -> tuple[int, int]:
    """``WxH`` with each side in [1, 16384]."""
    parts = text.lower().split("x")
    try:
        w, h = (int(p) for p in parts)
    except ValueError:
        raise UsageError(f"--size {text!r} is not WxH: allowed e.g. 1280x720") from None
    if not (1 <= w <= 16384 and 1 <= h <= 16384):
        raise UsageError(f"--size {text!r} is out of range: allowed 1..16384 on each side")
    return w, h


@dataclass
class Session:
    gpu: Gpu
    scene: Scene
    params: ParamSet

    def release(self) -> None:
        self.scene.release()
        self.gpu.release()


def scene_params(scene_name: str, shader_root=None, sets: Iterable[str] = (),
                 preset: str | None = None) -> ParamSet:
    """Validate a scene's parameters without touching the GPU (annotations are read from the
    GLSL files directly)."""
    cls = get_scene(scene_name)
    library = ShaderLibrary(None, resolve_shader_root(shader_root))
    params = cls.declare_params(library)
    if preset:
        params.load_preset(Path(preset))
    for assignment in sets:
        params.set_from_string(assignment)
    return params


def open_session(scene_name: str, params: ParamSet | None = None, shader_root=None, ctx=None,
                 camera: Camera | None = None) -> Session:
    cls = get_scene(scene_name)
    root = resolve_shader_root(shader_root)
    if params is None:
        params = scene_params(scene_name, root)
    gpu = Gpu(ctx, root)
    return Session(gpu, cls(gpu, params, camera), params)


def render_frames(session: Session, size: tuple[int, int], frames: int = 1, fps: float = 30.0,
                  progress: bool = False) -> Iterator[np.ndarray]:
    """Yield ``frames`` linear-radiance images ``(h, w, 4)``; time advances 1/fps per frame."""
    target = session.gpu.target("output", "scene radiance", size)
    try:
        for i in range(frames):
            frame = session.scene.frame(size, dt=0.0 if i == 0 else 1.0 / fps)
            session.scene.render(frame, target)
            image = target.read()
            if progress:  # before the yield: a consumer may never resume after the last frame
                _progress(i + 1, frames)
            yield image
    finally:
        session.gpu.free(target)
        if progress:
            sys.stderr.write("\n")


def _progress(done: int, total: int, width: int = 30) -> None:
    filled = int(width * done / total)
    sys.stderr.write(f"\rrendering [{'#' * filled}{'.' * (width - filled)}] {done}/{total} frames")
    sys.stderr.flush()
