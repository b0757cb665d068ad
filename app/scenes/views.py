"""Views: named, curated starting points of a scene, each showing one lesson at its best.

A view is a TOML preset in ``resources/presets/views/<scene>/<name>.toml``: a ``[view]`` table
says what it shows and where the camera stands, the other tables are parameter groups as in any
preset (applied over the scene's defaults, before the user's ``--preset`` and ``--set``)::

    [view]
    title = "Evening sail"                 # one line: what the picture is
    lesson = "the sun's glitter path …"    # one line: what it teaches, naming its section
    camera = [0.0, 6.0, 20.0, 200.0, -4.0, 55.0]   # x, y, z, yaw, pitch[, fov] (optional)
    time = 18.4                            # the hour (scenes with a day–night sky; optional)
    frames = 8                             # frames to run before the picture (optional, 1)
    order = 1                              # where the view is listed (optional)

    [ocean]
    wind = 12.0

``natura scenes`` lists every scene's views, ``natura render|window SCENE --view NAME`` starts
from one, the window's panel switches between them, and ``tools/gallery.py`` renders them all.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import ParamError, UsageError, quote
from ..params import ParamSet, read_preset_text
from ..sim.camera import Camera
from .base import PRESETS

VIEWS = PRESETS / "views"
_KEYS = {"title", "lesson", "camera", "time", "frames", "order"}


@dataclass(frozen=True)
class View:
    scene: str
    name: str
    title: str
    lesson: str
    path: Path
    camera: tuple[float, ...] | None = None
    time: float | None = None
    frames: int = 1
    order: int = 100
    tables: dict[str, Any] = field(default_factory=dict)

    def apply(self, params: ParamSet) -> None:
        """Set the view's parameters (and its hour) on ``params``."""
        for group, table in self.tables.items():
            for key, value in table.items():
                try:
                    params.set(f"{group}.{key}", value)
                except ParamError as exc:
                    raise ParamError(f"view {self.scene}/{self.name} ({quote(str(self.path), 40)}):"
                                     f" {exc}") from None
        if self.time is not None:
            if "time.hour" not in params:
                raise ParamError(f"view {self.scene}/{self.name}: time = {self.time} but the "
                                 "scene has no time of day: allowed only with a day–night sky")
            params.set("time.hour", self.time % 24.0)

    def place(self, camera: Camera) -> bool:
        """Put ``camera`` where the view stands; False when the view leaves it to the scene."""
        if self.camera is None:
            return False
        camera.set(position=self.camera[:3])
        camera.set(**dict(zip(("yaw", "pitch", "fov"), self.camera[3:])))
        return True


def _parse(scene: str, path: Path) -> View:
    text = read_preset_text(path)
    where = f"view {quote(str(path), 50)}"
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ParamError(f"{where} is not valid TOML ({str(exc)[:60]})") from None
    head = data.pop("view", None)
    if not isinstance(head, dict):
        raise ParamError(f"{where} has no [view] table: allowed a [view] table with title and "
                         "lesson, then parameter groups")
    unknown = set(head) - _KEYS
    if unknown:
        raise ParamError(f"{where}: unknown key {sorted(unknown)[0]!r} in [view]: allowed "
                         f"{', '.join(sorted(_KEYS))}")
    for key in ("title", "lesson"):
        if not isinstance(head.get(key), str) or not head[key].strip():
            raise ParamError(f"{where}: [view] {key} must be a non-empty string")
    camera = head.get("camera")
    if camera is not None:
        ok = (isinstance(camera, list) and 3 <= len(camera) <= 6
              and all(isinstance(v, (int, float)) and math.isfinite(v) for v in camera))
        if not ok:
            raise ParamError(f"{where}: [view] camera must be [x, y, z, yaw, pitch, fov] "
                             "(3 to 6 finite numbers)")
    time = head.get("time")
    if time is not None and not (isinstance(time, (int, float)) and 0 <= time <= 24):
        raise ParamError(f"{where}: [view] time must be an hour in [0, 24]")
    frames = head.get("frames", 1)
    if not (isinstance(frames, int) and 1 <= frames <= 600):
        raise ParamError(f"{where}: [view] frames must be an integer in [1, 600]")
    for group, table in data.items():
        if not isinstance(table, dict):
            raise ParamError(f"{where}: {group!r} must be a table of parameters")
    return View(scene, path.stem, head["title"].strip(), head["lesson"].strip(), path,
                tuple(float(v) for v in camera) if camera is not None else None,
                float(time) if time is not None else None, frames, int(head.get("order", 100)),
                data)


def views_of(scene: str) -> list[View]:
    """The scene's views, in their order (then by name)."""
    folder = VIEWS / scene
    if not folder.is_dir():
        return []
    views = [_parse(scene, p) for p in sorted(folder.glob("*.toml"))]
    return sorted(views, key=lambda v: (v.order, v.name))


def get_view(scene: str, name: str) -> View:
    views = views_of(scene)
    for view in views:
        if view.name == name:
            return view
    allowed = ", ".join(v.name for v in views) or "none (this scene has no views)"
    raise UsageError(f"--view {quote(name, 40)}: scene {scene!r} has no such view: allowed "
                     f"{allowed}")
