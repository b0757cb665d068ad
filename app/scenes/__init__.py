"""The scene registry: every module of this package that defines a :class:`~.base.Scene`
subclass with a ``name`` adds it (no central list to edit); ``natura scenes`` lists them by
their ``order``, then name.

To add a scene, create ``app/scenes/<name>.py`` with one Scene subclass naming its effects.
"""

from __future__ import annotations

import importlib
import pkgutil

from ..errors import UsageError
from .base import Scene

DEFAULT_SCENE = "sky"

#: modules of this package that are not scenes
_NOT_SCENES = {"base", "keymaps"}


def _discover() -> dict[str, type[Scene]]:
    found: list[type[Scene]] = []
    for info in pkgutil.iter_modules(__path__):
        if info.name in _NOT_SCENES or info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        for value in vars(module).values():
            if (isinstance(value, type) and issubclass(value, Scene) and value is not Scene
                    and value.__module__ == module.__name__ and value.name):
                found.append(value)
    found.sort(key=lambda cls: (cls.order, cls.name))
    scenes: dict[str, type[Scene]] = {}
    for cls in found:
        if cls.name in scenes:
            raise RuntimeError(f"two scenes are named {cls.name!r}: "
                               f"{scenes[cls.name].__module__}, {cls.__module__}")
        scenes[cls.name] = cls
    return scenes


SCENES: dict[str, type[Scene]] = _discover()


def get_scene(name: str) -> type[Scene]:
    try:
        return SCENES[name]
    except KeyError:
        raise UsageError(f"unknown scene {name!r}: allowed {', '.join(SCENES)}") from None
