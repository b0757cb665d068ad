"""GPU textures of bakes for one effect: baked (or read from the cache) on first use and again
whenever a spec changes, with progress reported through ``gpu.progress`` (the window's bar)."""

from __future__ import annotations

from .core import Baked, bake
from .params import DetailBake, ShapeBake, WeatherBake

#: the spec class of each kind of the default bakes, read from the ``bake_*`` parameters
KINDS = {"shape": ShapeBake, "detail": DetailBake, "weather": WeatherBake}


class BakedTextures:
    def __init__(self, gpu, owner: str):
        self.gpu = gpu
        self.owner = owner
        self.held: dict[str, tuple] = {}  # kind → (spec, Baked, texture)
        self.last: Baked | None = None  # the most recent bake or cache load

    def get(self, spec):
        """The texture for ``spec`` (a ShapeBake, DetailBake or WeatherBake)."""
        kind = spec.kind
        held = self.held.get(kind)
        if held is None or held[0] != spec:
            if held is not None:
                self.gpu.free(held[2])
            hook = getattr(self.gpu, "progress", None)
            label = f"baking {kind} {spec.size}{'²' if kind == 'weather' else '³'}"
            result = bake(self.gpu, spec, progress=(lambda f: hook(label, f)) if hook else None)
            self.last = result
            self.held[kind] = (spec, result, result.texture(self.gpu, self.owner))
        return self.held[kind][2]

    def from_params(self, kind: str, params):
        """The texture of ``kind`` (shape, detail, weather) as its ``bake_*`` parameters say.
        One bake per kind is held, replaced on a change: nothing else keeps a ``Baked`` (8 MB
        of texels for the default shape bake), so live edits do not grow the process."""
        cls = KINDS[kind]
        return self.get(cls.from_values(params.values(cls.group)))

    def baked(self, kind: str) -> Baked:
        """The :class:`Baked` behind the texture of ``kind`` (its texels, path, cache status)."""
        return self.held[kind][1]
