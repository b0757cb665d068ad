"""The GPU side of the noise library: Perlin permutation textures, and a probe that evaluates
any GLSL noise expression at given points.

* :class:`GradientNoiseTextures` — the 256×1 R32F permutation texture that
  ``glsl/common/noise_perlin.glsl`` reads through ``uPerlinPermutation``, one per seed,
  created on first use through ``gpu.texture(owner, ...)`` so the allocation is listed under
  the effect that asked for it. An effect that uses ``PerlinNoise3`` needs one line::

      GradientNoiseTextures(self.gpu, self.name).bind(prog, seed, unit=3)

* :class:`NoiseProbe` — runs ``glsl/tests/noise_probe.comp`` (compute, GL ≥ 4.3) with the
  expression in the ``NOISE_FUNC`` define, at points given as an (N, ≤4) array, and returns
  the (N, 4) float32 results: how tests and accuracy benches compare the GLSL with the numpy
  twins (``app.sim.noise.gradient``, ``cellular``, ``fractal``).
"""

from __future__ import annotations

import shutil
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import moderngl
import numpy as np

from ..errors import GpuUnavailableError
from ..sim.noise import gradient

if TYPE_CHECKING:
    from ..gpu.device import Gpu

#: The sampler uniform of noise_perlin.glsl.
PERMUTATION_UNIFORM = "uPerlinPermutation"
PROBE_PROGRAM = "tests/noise_probe"
_PROBE_GROUP = 64  # local_size_x of noise_probe.comp
_MAX_GROUPS = 65535  # the GL minimum for GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]


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


class NoiseProbe:
    """Evaluate GLSL noise expressions at points on the GPU (compute shaders, GL ≥ 4.3).

    ``includes`` names extra GLSL files (resolved like ``#include``: ``glsl/common`` first) to
    compile in before the probe, e.g. ``("noise_value.glsl",)`` for the thesis's value noise;
    their own samplers can be bound with ``textures=`` in :meth:`evaluate`.
    """

    def __init__(self, gpu: Gpu, owner: str = "noise-probe", includes: Sequence[str] = ()):
        if not gpu.caps.compute:
            raise GpuUnavailableError(
                "the noise probe needs compute shaders (GL 4.3); this context has "
                f"{gpu.caps.describe()}")
        self.gpu = gpu
        self.owner = owner
        self.includes = tuple(includes)
        self.permutations = GradientNoiseTextures(gpu, owner)
        self._wrapper: Path | None = None
        self._tmpdir: str | None = None

    def _stage(self) -> dict[str, str]:
        if not self.includes:
            return {}
        if self._wrapper is None:
            # the probe's text follows the extra includes (an include must stay inside the
            # shader folder, and this wrapper lives in a temporary folder); its own includes
            # are common/ files, found from anywhere
            probe = (self.gpu.shaders.root / f"{PROBE_PROGRAM}.comp").read_text(encoding="utf-8")
            body = probe.split("\n", 1)[1] if probe.startswith("#version") else probe
            self._tmpdir = tempfile.mkdtemp(prefix="natura-noise-probe-")
            lines = ["#version 430", "// generated by app.render.noise.NoiseProbe"]
            lines += [f'#include "{name}"' for name in self.includes]
            lines.append(body)
            self._wrapper = Path(self._tmpdir) / "noise_probe.comp"
            self._wrapper.write_text("\n".join(lines) + "\n", encoding="utf-8")
        return {"comp": str(self._wrapper)}

    def program(self, expr: str, defines: Mapping[str, Any] | None = None):
        """The compiled probe for ``expr`` (shared by later calls with the same text)."""
        all_defines = dict(defines or {})
        all_defines["NOISE_FUNC"] = expr
        return self.gpu.program(self.owner, PROBE_PROGRAM, all_defines, **self._stage())

    def evaluate(self, expr: str, points, *, perlin_seed: int | None = None, seed: int = 0,
                 period=(1, 1, 1, 1), octaves: int = 1, lacunarity: float = 2.0, gain: float = 0.5,
                 params=(0.0, 0.0, 0.0, 0.0),
                 textures: Mapping[str, moderngl.Texture] | None = None,
                 uniforms: Mapping[str, Any] | None = None,
                 defines: Mapping[str, Any] | None = None) -> np.ndarray:
        """``expr`` (GLSL, in terms of the point ``P``) at each row of ``points`` (N, ≤4).

        ``perlin_seed`` picks the permutation texture; ``seed``, ``period``, ``octaves``,
        ``lacunarity``, ``gain`` and ``params`` fill the probe's uniforms; ``textures`` binds
        extra samplers (uniform name → texture; units assigned by ``Program.bind_textures``);
        ``uniforms`` sets any other uniform. Returns float32 (N, 4)."""
        pts = np.asarray(points, dtype=np.float32)
        if pts.ndim == 1:
            pts = pts[:, None]
        n, dims = pts.shape
        if dims > 4:
            raise ValueError(f"probe points have {dims} coordinates: allowed 1 to 4")
        padded = np.zeros((n, 4), dtype=np.float32)
        padded[:, :dims] = pts
        prog = self.program(expr, defines)
        prog.bind_textures({**self.permutations.textures(perlin_seed), **(textures or {})})
        period = tuple(int(v) for v in np.broadcast_to(np.asarray(period), (4,)))
        prog.set_many({
            "uProbeCount": n, "uProbeSeed": int(seed) & 0xFFFFFFFF, "uProbePeriod": period,
            "uProbeOctaves": int(octaves), "uProbeLacunarity": float(lacunarity),
            "uProbeGain": float(gain), "uProbeParams": tuple(float(v) for v in params),
        })
        prog.set_many(dict(uniforms or {}))
        ctx = self.gpu.ctx
        src = ctx.buffer(padded.tobytes())
        dst = ctx.buffer(reserve=max(n, 1) * 16)
        try:
            src.bind_to_storage_buffer(0)
            dst.bind_to_storage_buffer(1)
            step = _PROBE_GROUP * _MAX_GROUPS
            for first in range(0, n, step):
                prog.set("uProbeFirst", first)
                prog.program.run(group_x=-(-min(step, n - first) // _PROBE_GROUP))
            ctx.memory_barrier()
            out = np.frombuffer(dst.read(), dtype=np.float32).reshape(-1, 4)[:n].copy()
        finally:
            src.release()
            dst.release()
        return out

    def release(self) -> None:
        self.permutations.release()
        self.gpu.release_owner(self.owner)
        if self._tmpdir:
            shutil.rmtree(self._tmpdir, ignore_errors=True)
            self._tmpdir = None
            self._wrapper = None
