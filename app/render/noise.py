"""The GPU side of the noise library: Perlin permutation textures and the value-noise source.

* :class:`GradientNoiseTextures` — the 256×1 R32F permutation texture that
  ``glsl/common/noise_perlin.glsl`` reads through ``uPerlinPermutation``, one per seed,
  created on first use through ``gpu.texture(owner, ...)`` so the allocation is listed under
  the effect that asked for it. An effect that uses ``PerlinNoise3`` needs one line::

      GradientNoiseTextures(self.gpu, self.name).bind(prog, seed, unit=3)

The probe that evaluates GLSL noise at points for the tests is ``tests/helpers/noise_probe.py``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import moderngl
import numpy as np

from ..sim.noise import gradient

if TYPE_CHECKING:
    from ..gpu.device import Gpu

#: The sampler uniform of noise_perlin.glsl.
PERMUTATION_UNIFORM = "uPerlinPermutation"


def _set_uniform(prog: Any, name: str, value: Any) -> None:
    """Set a uniform on an ``app.gpu.shaders.Program`` or a raw moderngl program, tolerating
    uniforms the compiler removed."""
    if hasattr(prog, "set"):
        prog.set(name, value)
    elif name in prog:
        prog[name].value = value


def value_noise_texture(gpu: "Gpu", owner: str, seed: int) -> moderngl.Texture:
    """The wood thesis's random source (256×256 RGBA8, NEAREST, repeat) for
    ``glsl/common/noise_value.glsl`` (read with texelFetch), allocated under ``owner``."""
    from ..sim.noise.value import random_texture

    return gpu.texture(owner, "value noise source", (256, 256), 4, random_texture(seed).tobytes(),
                       dtype="f1", filter=(moderngl.NEAREST, moderngl.NEAREST), repeat=True)


class GradientNoiseTextures:
    """Perlin permutation textures for one owner (effect or scene), one per seed.

    Seed ``None`` or 0 is Perlin's reference table; others are
    ``numpy.random.default_rng(seed).permutation(256)`` — exactly the tables
    ``app.sim.noise.gradient`` uses, so GPU and twin agree."""

    def __init__(self, gpu: Gpu, owner: str):
        self.gpu = gpu
        self.owner = owner
        self._textures: dict[int, moderngl.Texture] = {}

    def texture(self, seed: int | None = None) -> moderngl.Texture:
        """The permutation texture for ``seed`` (created on first request)."""
        key = gradient.seed_key(seed)
        tex = self._textures.get(key)
        if tex is not None and not any(a.obj is tex for a in self.gpu.allocations):
            tex = None  # released with its owner meanwhile: make a new one
        if tex is None:
            data = np.ascontiguousarray(gradient.permutation(key), dtype="f4").tobytes()
            tex = self.gpu.texture(self.owner, f"perlin-permutation-seed{key}", (256, 1), 1,
                                   data=data, dtype="f4",
                                   filter=(moderngl.NEAREST, moderngl.NEAREST))
            self._textures[key] = tex
        return tex

    def textures(self, seed: int | None = None,
                 uniform: str = PERMUTATION_UNIFORM) -> dict[str, moderngl.Texture]:
        """``{sampler: texture}`` for ``Program.bind_textures`` (units assigned there)."""
        return {uniform: self.texture(seed)}

    def bind(self, prog: Any, seed: int | None = None, unit: int = 0,
             uniform: str = PERMUTATION_UNIFORM) -> moderngl.Texture:
        """Bind the texture for ``seed`` to texture unit ``unit`` and point ``uniform`` of
        ``prog`` (a library ``Program`` or a moderngl program) at it."""
        tex = self.texture(seed)
        tex.use(location=unit)
        _set_uniform(prog, uniform, unit)
        return tex

    def release(self) -> None:
        for tex in self._textures.values():
            if any(a.obj is tex for a in self.gpu.allocations):
                self.gpu.free(tex)
        self._textures.clear()
