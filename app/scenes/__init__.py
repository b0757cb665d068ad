"""The scene registry: every module of this package that defines a :class:`~.base.Scene`
subclass with a ``name`` adds it (no central list to edit); ``natura scenes`` lists them by
their ``order``, then name.

To add a scene, create ``app/scenes/<name>.py`` with one Scene subclass naming its effects.
"""

from __future__ import annotations

import importlib
import pkgutil
from typing import Iterator, MutableMapping

from ..errors import UsageError
from .base import Scene

#: what ``natura`` renders with no scene named and no display; with one, the scene picker
#: (app/ui/picker.py) opens with this scene highlighted first
DEFAULT_SCENE = "maritime"

#: modules of this package that are not scenes
_NOT_SCENES = {"base", "keymaps", "views"}


def _scenes_in(module_name: str) -> list[type[Scene]]:
    """The named Scene subclasses ``app/scenes/<module_name>.py`` defines."""
    module = importlib.import_module(f"{__name__}.{module_name}")
    return [value for value in vars(module).values()
            if isinstance(value, type) and issubclass(value, Scene) and value is not Scene
            and value.__module__ == module.__name__ and value.name]


def _discover() -> dict[str, type[Scene]]:
    found = [cls for info in pkgutil.iter_modules(__path__)
             if info.name not in _NOT_SCENES and not info.name.startswith("_")
             for cls in _scenes_in(info.name)]
    found.sort(key=lambda cls: (cls.order, cls.name))
    scenes: dict[str, type[Scene]] = {}
    for cls in found:
        if cls.name in scenes:
            raise RuntimeError(f"two scenes are named {cls.name!r}: "
                               f"{scenes[cls.name].__module__}, {cls.__module__}")
        scenes[cls.name] = cls
    return scenes


class _Registry(MutableMapping[str, type[Scene]]):
    """``SCENES``: every scene by ``order``, discovered on first iteration. Looking one name up
    before that imports ``app/scenes/<name>.py`` alone when it defines that scene, so
    ``natura render sky`` does not import every scene's effects."""

    def __init__(self) -> None:
        self._all: dict[str, type[Scene]] | None = None

    def _discovered(self) -> dict[str, type[Scene]]:
        if self._all is None:
            self._all = _discover()
        return self._all

    def __getitem__(self, name: str) -> type[Scene]:
        if self._all is None:
            cls = _own_module(name)
            if cls is not None:
                return cls
        return self._discovered()[name]

    def __contains__(self, name: object) -> bool:
        try:
            self[name]  # type: ignore[index]
        except KeyError:
            return False
        return True

    def __setitem__(self, name: str, cls: type[Scene]) -> None:  # tests register a scene
        self._discovered()[name] = cls

    def __delitem__(self, name: str) -> None:
        del self._discovered()[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._discovered())

    def __len__(self) -> int:
        return len(self._discovered())

    def __repr__(self) -> str:
        return repr(self._discovered())


def _own_module(name: object) -> type[Scene] | None:
    """The scene ``name`` from ``app/scenes/<name>.py`` alone, when that module defines it."""
    if (not isinstance(name, str) or not name.isidentifier() or name in _NOT_SCENES
            or name.startswith("_")):
        return None
    if not any(info.name == name for info in pkgutil.iter_modules(__path__)):
        return None
    return next((cls for cls in _scenes_in(name) if cls.name == name), None)


SCENES: MutableMapping[str, type[Scene]] = _Registry()


def get_scene(name: str) -> type[Scene]:
    try:
        return SCENES[name]
    except KeyError:
        raise UsageError(f"unknown scene {name!r}: allowed {', '.join(SCENES)}") from None
